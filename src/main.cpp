// tileshade command line: render, devices, scene export (and the benchmark, see src/bench/).
#include <iostream>
#include <new>

#include <CLI/CLI.hpp>

#include "bench/bench_cli.h"
#include "check/check_cli.h"
#include "cl/cl_context.h"
#include "cli/render_job.h"
#include "scene/scene_loader.h"
#include "techniques/technique.h"
#include "util/error.h"
#include "util/option_values.h"
#include "tileshade/version.h"

namespace {

void printDevices() {
  auto devices = ts::listDevices();
  if (devices.empty()) {
    std::cout << "no OpenCL devices (install pocl-opencl-icd or a GPU driver's ICD)\n";
    return;
  }
  for (const auto& d : devices)
    std::cout << d.index << ": [" << d.type << "] " << d.platform << " / " << d.name << " ("
              << d.computeUnits << " compute units, " << (d.globalMemBytes >> 20) << " MiB, local "
              << (d.localMemBytes >> 10) << " KiB)\n";
}

// Checks a number option on the text as typed: CLI11 converts 1e39 to inf before the option's
// own check would see it, and the error would echo "inf".
CLI::Validator typedNumber(ts::NumberRule rule) {
  return CLI::Validator([rule](std::string& text) { return ts::numberTextProblem(text, rule); },
                        "");
}

// "unknown subcommand 'X' (known: ...)" when the deepest subcommand given wants one and the
// next argument names none; "" otherwise (CLI11 says only "A subcommand is required").
std::string unknownSubcommand(CLI::App& app) {
  CLI::App* at = &app;
  while (!at->get_subcommands().empty()) at = at->get_subcommands().front();
  std::vector<std::string> rest = at->remaining();
  if (at->get_require_subcommand_min() == 0 || rest.empty() || rest.front().rfind("-", 0) == 0)
    return "";
  std::string known;
  for (const CLI::App* sub : at->get_subcommands([](const CLI::App*) { return true; }))
    known += (known.empty() ? "" : ", ") + sub->get_name();
  return "unknown subcommand '" + rest.front() + "' (known: " + known + ")";
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "tileshade: tiled shading of a G-buffer in OpenCL, and a lab that measures "
      "light-culling techniques for speed and error"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tileshade ") + TILESHADE_VERSION);

  // render
  ts::RenderOptions render;
  // Knobs with a name table arrive as text and are parsed through it after the command line.
  std::string tile = "16", format = ts::toString(render.format),
              raster = ts::toString(render.raster), culling = ts::toString(render.culling),
              spotCulling = ts::toString(render.spotCulling), math = ts::toString(render.math),
              lanes = ts::lanesName(render.lanes),
              shadowStorage = ts::toString(render.shadowStorage);
  auto* renderCmd = app.add_subcommand("render", "render one frame with one or more techniques");
  auto* sceneOpt = renderCmd
                       ->add_option("--scene", render.scene,
                                    "builtin:street, builtin:atrium, or a .gltf/.glb path")
                       ->capture_default_str();
  renderCmd->add_option("--lights", render.lightSet,
                        "light set (street: many, few; atrium: small, big, mixed, and the "
                        "thesis's scenarios thesis-small, thesis-big, thesis-big-shadows, "
                        "thesis-mixed: big lights casting); for glTF, the file's own lights "
                        "unless given");
  renderCmd->add_option("--light-count", render.lightCount, "number of lights (-1: the set's own)")
      ->capture_default_str();
  renderCmd
      ->add_option("--light-range", render.lightRange,
                   "override every light's range (0: keep; finite, >= 0)")
      ->capture_default_str()
      ->check(typedNumber(ts::NumberRule::AtLeastZero));
  renderCmd->add_option("--variant", render.variant,
                        "built-in scene variants, a comma list of: " +
                            joined(ts::builtinVariants()) + " (scenes/README.md)");
  std::string normalMaps = "on";
  renderCmd
      ->add_option("--normal-maps", normalMaps,
                   "apply the glTF materials' normal maps (normalTexture): on, off (the "
                   "interpolated vertex normals)")
      ->capture_default_str()
      ->check(CLI::IsMember({"on", "off"}));
  renderCmd->add_option("--shadows", render.shadows,
                        "which lights cast shadows: none, all, or N (the N lights of largest "
                        "range); default the scene's own (glTF extras castsShadow). Their "
                        "shadow maps are drawn into one atlas (stats.json shadow_maps, --dump "
                        "writes it) and every technique shades with them, the forward ones in "
                        "their fragment shader (docs/shadows.md)");
  renderCmd
      ->add_option("--shadow-filter", render.shadowFilter,
                   "how shading samples a shadow map: none (one texel's depth comparison), "
                   "pcf2, pcf3, pcf5 (N x N comparisons averaged)")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "pcf2", "pcf3", "pcf5"}));
  renderCmd
      ->add_option("--shadow-bias", render.shadowBias,
                   "depth bias CONSTANT,SLOPE in texels' world footprint at the receiver: "
                   "footprint * (C + S tan(angle between normal and light) N/2), N the "
                   "filter's taps a side (none: 1); or receiver,C: each tap compares the "
                   "receiver plane's depth at its texel, bias footprint * C; docs/shadows.md")
      ->capture_default_str();
  renderCmd
      ->add_option("--shadow-map-size", render.shadowMapSize,
                   "texels a side of a point or spot light's shadow-map face, a power of two "
                   "16..8192 (directional lights: 4x, at most 8192); lights lose resolution to "
                   "--shadow-budget, the least important first")
      ->capture_default_str();
  renderCmd
      ->add_option("--shadow-budget", render.shadowBudgetMB,
                   "the shadow atlas's memory budget in MB (MiB), > 0 and <= 4096")
      ->capture_default_str();
  renderCmd
      ->add_option("--shadow-storage", shadowStorage,
                   "where the shadow maps live while shading: " + ts::shadowStorageNames().help() +
                       "; the other techniques refuse per-light (docs/shadows.md)")
      ->capture_default_str();
  std::string blend = "refuse";
  renderCmd
      ->add_option("--blend", blend,
                   "glTF alphaMode BLEND materials: " + ts::blendPolicyNames().help())
      ->capture_default_str();
  renderCmd
      ->add_option("--shading-model", render.shadingModel,
                   "auto (the scene's own: metallic-roughness for glTF, blinn-phong for the "
                   "built-ins), " +
                       ts::shadingModelNames().list())
      ->capture_default_str();
  renderCmd
      ->add_option("--features", render.features,
                   "what the kernels and the G-buffer model: auto (what the scene needs), "
                   "general (everything), or a comma list of specular, emissive, textures, "
                   "point, spot, directional, normal_maps, shadows (docs/features.md)")
      ->capture_default_str();
  renderCmd
      ->add_option("--light-threshold", render.lightThreshold,
                   "ranges from the attenuation threshold t: r = sqrt(max(C)/t), e.g. "
                   "0.01953125 (5/256); 0 keeps the scene's ranges (finite, >= 0)")
      ->capture_default_str()
      ->check(typedNumber(ts::NumberRule::AtLeastZero));
  renderCmd->add_option("--culling", culling, "per-tile light test: " + ts::cullTestNames().help())
      ->capture_default_str();
  renderCmd
      ->add_option("--spot-culling", spotCulling,
                   "spot lights culled as: " + ts::spotCullingNames().help())
      ->capture_default_str();
  renderCmd->add_flag("--depth-split", render.depthSplit,
                      "tiled: split each tile's depth range at its middle and cull against both "
                      "halves (fewer lights at depth discontinuities; docs/techniques.md)");
  renderCmd->add_option("--math", math, "shading arithmetic: " + ts::mathModeNames().help())
      ->capture_default_str();
  renderCmd
      ->add_option("--lanes", lanes, "pixels shaded together per light: " + ts::laneNames().help())
      ->capture_default_str();
  renderCmd->add_option("--seed", render.seed, "seed of the built-in scenes")
      ->capture_default_str();
  renderCmd
      ->add_option("--technique", render.techniques,
                   "technique(s): " + joined(ts::techniqueNames()) + ", or all")
      ->capture_default_str();
  renderCmd->add_option("--tile", tile, "tile size N or WxH (pixels)")->capture_default_str();
  renderCmd
      ->add_option("--slices", render.clusterSlices,
                   "depth slices of clustered and clustered-forward")
      ->capture_default_str();
  auto* rasterOpt =
      renderCmd
          ->add_option("--raster", raster,
                       "rasterizer of the G-buffer: " + ts::rasterBackendNames().help())
          ->capture_default_str();
  renderCmd
      ->add_option("--msaa", render.msaa,
                   "MSAA samples a pixel: 1, 2, 4 or 8 (above 1: --raster gl; tiled-forward and "
                   "tiled-forward-prez shaded per fragment and resolved by OpenGL, tiled and "
                   "clustered from a per-sample G-buffer, its edge pixels shaded per sample; "
                   "--check against the "
                   "per-sample reference; docs/techniques.md)")
      ->capture_default_str();
  auto* gbufferInOpt = renderCmd->add_option(
      "--gbuffer-in", render.gbufferIn,
      "shade a G-buffer read from files instead of a scene: a folder written by --dump, or a "
      "descriptor .json naming another renderer's EXR channels (docs/output-formats.md); size, "
      "camera, lights and shading model come from the files (the options that set them are "
      "refused), the layout too unless --gbuffer is given");
  auto* gbufferOpt = renderCmd
                         ->add_option("--gbuffer", format,
                                      "G-buffer precision: " + ts::gbufferFormatNames().help() +
                                          "; see docs/accuracy.md")
                         ->capture_default_str();
  renderCmd->add_option("--width", render.width, "image width")->capture_default_str();
  renderCmd->add_option("--height", render.height, "image height")->capture_default_str();
  renderCmd->add_option("--frame", render.frame, "frame of the scene's camera path")
      ->capture_default_str();
  renderCmd->add_option("--device", render.device,
                        "OpenCL device: cpu, gpu, an index or a name substring (see `devices`); "
                        "default: first GPU, else CPU, or $TILESHADE_DEVICE");
  renderCmd->add_option("--out", render.outDir, "output folder")->capture_default_str();
  renderCmd->add_option("--exposure", render.exposure, "exposure of the tone-mapped PNG (> 0)")
      ->capture_default_str()
      ->check(typedNumber(ts::NumberRule::AboveZero));
  renderCmd->add_flag("--check", render.check,
                      "compare with the double-precision reference (error, missed lights; "
                      "progress on stderr when it is long)");
  renderCmd->add_flag("--heatmap", render.heatmap,
                      "with --check (needs it): error.png, a log-scale heat map of the error per "
                      "pixel");
  renderCmd->add_flag("--exact-visibility", render.exactVisibility,
                      "exact visibility of every (pixel, shadow-casting light) pair by ray "
                      "queries against the scene's triangles (Embree): visibility_exact.exr (a "
                      "channel per light, the first 16: 0 occluded, 1 lit, 2 not applicable) and "
                      "stats.json exact_visibility; the shadow maps against it: wrong pairs "
                      "(false shadow, light leak), the image error of the reference shaded with "
                      "the maps against one shaded with exact visibility (shadow_error.exr) and "
                      "each technique's error_vs_exact (docs/shadows.md)");
  renderCmd->add_flag("--dump", render.dump,
                      "also write gbuffer.exr (decoded shading inputs), lights.json and "
                      "gbuffer.json (the descriptor --gbuffer-in reads); with shadow-casting "
                      "lights, shadow_atlas.exr and shadow_atlas.json");
  // An imported G-buffer brings its own scene, size, frame, lights and shading model.
  for (const char* name :
       {"--lights", "--light-count", "--light-range", "--light-threshold", "--seed", "--width",
        "--height", "--frame", "--variant", "--normal-maps", "--shadows", "--shadow-map-size",
        "--shadow-budget", "--shadow-filter", "--shadow-bias", "--shadow-storage", "--blend",
        "--shading-model", "--msaa"})
    gbufferInOpt->excludes(renderCmd->get_option(name));
  gbufferInOpt->excludes(sceneOpt);
  gbufferInOpt->excludes(rasterOpt);

  // devices
  auto* devicesCmd = app.add_subcommand("devices", "list the OpenCL devices");

  // scene export
  auto* sceneCmd = app.add_subcommand("scene", "scene tools");
  sceneCmd->require_subcommand(1);
  std::string exportSpec, exportPath, exportLights, exportShadows;
  auto* exportCmd = sceneCmd->add_subcommand("export", "write a scene (with its lights) as glTF");
  exportCmd->add_option("scene", exportSpec, "scene spec, e.g. builtin:street")->required();
  exportCmd->add_option("path", exportPath, "output .gltf (buffers embedded) or .glb")->required();
  exportCmd->add_option("--lights", exportLights, "light set");
  exportCmd->add_option("--shadows", exportShadows,
                        "mark shadow-casting lights (extras castsShadow): none, all or N");

  // bench (src/bench/)
  ts::CliCommand bench = ts::addBenchCommand(app);
  // check (src/check/)
  ts::CliCommand check = ts::addCheckCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, like every other bad input (CLI11's default adds a second "Run with --help").
    std::string unknown = unknownSubcommand(app);
    std::cerr << "tileshade: error: " << (unknown.empty() ? e.what() : unknown)
              << " (see --help)\n";
    return 1;
  }
  try {
    if (*renderCmd) {
      auto [tw, th] = ts::parseTileSize(tile);
      render.tileWidth = tw;
      render.tileHeight = th;
      render.format = ts::gbufferFormatNames().parseOption("--gbuffer", format);
      render.raster = ts::rasterBackendNames().parseOption("--raster", raster);
      render.culling = ts::cullTestNames().parseOption("--culling", culling);
      render.spotCulling = ts::spotCullingNames().parseOption("--spot-culling", spotCulling);
      render.math = ts::mathModeNames().parseOption("--math", math);
      render.lanes = ts::laneNames().parseOption("--lanes", lanes);
      render.shadowStorage =
          ts::shadowStorageNames().parseOption("--shadow-storage", shadowStorage);
      render.normalMaps = normalMaps == "on";
      render.blend = ts::blendPolicyNames().parseOption("--blend", blend);
      render.keepInputLayout = gbufferOpt->count() == 0;
      ts::runRender(render);
    } else if (*bench.command) {
      bench.run();
    } else if (*check.command) {
      check.run();
    } else if (*devicesCmd) {
      printDevices();
    } else if (*exportCmd) {
      ts::checkExportPath(exportPath);  // before the scene is built
      ts::SceneOptions so;
      so.lightSet = exportLights;
      so.shadows = exportShadows;
      ts::Scene scene = ts::outOfMemoryAs("loading scene " + exportSpec,
                                          [&] { return ts::loadScene(exportSpec, so); });
      ts::exportGltf(scene, exportPath);
      std::cout << "wrote " << exportPath << " (" << scene.triangleCount() << " triangles, "
                << scene.lights.size() << " lights)\n";
    }
  } catch (const ts::Error& e) {
    std::cerr << "tileshade: error: " << e.what() << "\n";
    return 1;
  } catch (const cl::Error& e) {
    std::cerr << "tileshade: OpenCL error: " << e.what() << " (" << e.err() << ")\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "tileshade: error: out of memory (try a smaller image, fewer lights or a smaller "
                 "scene)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "tileshade: error: " << e.what() << "\n";
    return 1;
  }
  // The table and "wrote ..." lines: a failed stdout (a full disk behind a redirection) fails too.
  std::cout.flush();
  if (!std::cout) {
    std::cerr << "tileshade: error: cannot write to standard output\n";
    return 1;
  }
  return 0;
}
