#pragma once
// The hard cases of `tileshade check` (docs/hard-cases.md): small scenes built to stress one
// thing each — lights behind, around or straddling the camera, extreme ranges and depth ratios,
// lights on surfaces or in their planes, degenerate vectors, odd resolutions, light counts beyond
// every list, values at the edge of fp16 and fp32, a scene far from the origin. The list is data:
// adding a case is one entry in hardCases() (src/check/hard_cases.cpp).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "techniques/technique.h"

namespace ts {

// One case's frame: what the techniques render and what it is compared with.
struct HardCaseFrame {
  Scene scene;  // rendered at frame 0
  int width = 64;
  int height = 48;
  // The reference is shaded from this scene instead when given (same size, frame 0): the same
  // geometry elsewhere, e.g. at the origin for a scene moved 1e6 units away.
  std::optional<Scene> referenceScene;
  // Tile size, list sizes: the case's knobs (the G-buffer layout and lanes are the run's).
  TechniqueConfig config;
  // Lanes widths to run instead of the check's (e.g. every width for the list-overflow case).
  std::vector<int> lanes;
  // Through the import path: the rasterized frame written as another renderer's files and read
  // back by --gbuffer-in's reader (src/check/foreign_gbuffer.h); the reference is shaded from
  // what was read.
  bool throughImport = false;
};

struct HardCase {
  std::string name;         // "lights-behind-camera": what --case selects
  std::string description;  // one line for docs and `check --list`
  std::function<HardCaseFrame()> build;
};

const std::vector<HardCase>& hardCases();

}  // namespace ts
