#pragma once
// `tileshade render`: one frame of a scene, one or more techniques, files in an output folder.
#include <string>
#include <vector>

#include "render/pipeline_options.h"

namespace ts {

// The pipeline (PipelineOptions) and what `render` does with it.
struct RenderOptions : PipelineOptions {
  std::vector<std::string> techniques{"tiled"};  // "all" expands to every registered technique
  int frame = 0;                                 // of the scene's camera path
  std::string outDir = "out";
  bool check = false;            // compare against the double reference
  bool dump = false;             // write gbuffer.exr + lights.json
  bool heatmap = false;          // with check: error.png per technique
  bool exactVisibility = false;  // visibility_exact.exr + stats.json exact_visibility
  float exposure = 1.0f;         // PNG tone mapping
  std::string gbufferIn;         // "" = rasterize the scene; else G-buffer files to import
  bool keepInputLayout = false;  // with gbufferIn: encode in the files' layout, not `format`
};

// Throws ts::Error (one line naming the option) for any option that makes no sense: NaN, inf or
// negative numbers, zero or absurd sizes, --heatmap without --check, unknown names.
void validateRenderOptions(const RenderOptions& options);

// Runs the job, prints the table to stdout, writes the files. Throws ts::Error on bad input (every
// option is checked before any work) and when a file cannot be written.
void runRender(const RenderOptions& options);

}  // namespace ts
