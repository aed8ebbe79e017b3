// `import tileshade`: the public C++ API (include/tileshade/tileshade.h) for Python, with pybind11
// (docs/python.md). Names are the API's in snake_case; knobs are keyword arguments with the
// command's names (python_knobs.h); images are numpy arrays, stats dicts (python_results.h);
// G-buffers come from numpy planes (python_planes.h). A ts::Error is tileshade.Error (a
// RuntimeError) with the same one line the command prints.
#include <cmath>
#include <sstream>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "python_knobs.h"
#include "python_planes.h"
#include "python_results.h"
#include "tileshade/tileshade.h"
#include "tileshade/version.h"

namespace py = pybind11;
using namespace pybind11::literals;
using namespace tileshade_python;

namespace {

const char* lightTypeName(ts::LightType type) {
  switch (type) {
    case ts::LightType::Point: return "point";
    case ts::LightType::Spot: return "spot";
    case ts::LightType::Directional: return "directional";
  }
  return "?";
}

ts::LightType lightType(const std::string& name) {
  if (name == "point") return ts::LightType::Point;
  if (name == "spot") return ts::LightType::Spot;
  if (name == "directional") return ts::LightType::Directional;
  throw py::value_error("Light.type: '" + name + "' is none of point, spot, directional");
}

// The image as numpy HxWx4 float32 over the result's own memory: no copy; the array holds the
// Result object alive.
py::array imageView(py::object result) {
  auto& r = result.cast<ts::ShadeResult&>();
  const py::ssize_t h = r.height, w = r.width, f = sizeof(float);
  return py::array_t<float>({h, w, py::ssize_t(4)}, {w * 4 * f, 4 * f, f}, r.rgba.data(), result);
}

ts::ShadeResult shade(ts::Renderer& renderer, const ts::Frame& frame, bool check) {
  ts::ShadeOptions options;
  options.check = check;
  // Kernels run (and the reference may take seconds): other Python threads go on meanwhile.
  py::gil_scoped_release release;
  return renderer.shade(frame, options);
}

ts::Frame frameFromScene(ts::Device& device, const ts::SceneRequest& request) {
  py::gil_scoped_release release;
  return ts::Frame::fromScene(device, request);
}

// A bench config: a dict (as JSON through Python's json) or a JSON document into configJson, or a
// file's path into configPath (read by the library, as `bench --config` reads it).
void setBenchConfig(py::handle config, ts::BenchRequest& request) {
  if (py::isinstance<py::dict>(config)) {
    request.configJson = py::module_::import("json").attr("dumps")(config).cast<std::string>();
    return;
  }
  if (!py::isinstance<py::str>(config)) {
    throw py::type_error("bench: config: expected a dict, a JSON document or a path, got " +
                         std::string(py::str(py::type::handle_of(config).attr("__name__"))));
  }
  const std::string text = config.cast<std::string>();
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && text[first] == '{') request.configJson = text;
  else request.configPath = text;
}

py::list bench(py::handle config, const std::string& outDir, bool calibrate, bool quiet) {
  ts::BenchRequest request;
  setBenchConfig(config, request);
  request.outDir = outDir;
  request.calibrate = calibrate;
  request.quiet = quiet;
  std::vector<std::map<std::string, std::string>> rows;
  {
    py::gil_scoped_release release;
    rows = ts::runBench(request);
  }
  return benchRows(rows, outDir + "/bench.csv");
}

}  // namespace

PYBIND11_MODULE(tileshade, m) {
  m.doc() =
      "tileshade: tiled shading of a G-buffer in OpenCL, and a lab that measures light-culling "
      "techniques (docs/python.md).";
  m.attr("__version__") = TILESHADE_VERSION;
  // ts::Error (a std::runtime_error) as tileshade.Error, a RuntimeError, with its one line.
  py::register_exception<ts::Error>(m, "Error", PyExc_RuntimeError);
  m.attr("Error").attr("__doc__") =
      "A tileshade failure: its message is the one line `tileshade` prints.";

  m.def(
      "devices",
      [] {
        py::list list;
        for (const auto& d : ts::listDeviceDescriptions()) list.append(deviceDict(d));
        return list;
      },
      "Every OpenCL device of every platform, as dicts (index, platform, name, type, ...).");
  m.def(
      "techniques",
      [] {
        py::list list;
        for (const auto& t : ts::listTechniques()) {
          list.append(py::dict(
              "name"_a = t.name, "description"_a = t.description, "draws_scene"_a = t.drawsScene,
              "reuses_shadow_maps"_a = t.reusesShadowMaps,
              "hybrid_transparency"_a = t.hybridTransparency, "multisamples"_a = t.multisamples));
        }
        return list;
      },
      "The techniques, as dicts (name, description, draws_scene: a forward technique, which needs "
      "a frame rasterized with raster=\"gl\"; reuses_shadow_maps: may use shadow_storage="
      "\"per-light\"; hybrid_transparency: a G-buffer technique that shades glass; multisamples: "
      "shades msaa above 1).");

  py::class_<ts::Device>(m, "Device", "An OpenCL device (spec as `tileshade render --device`).")
      .def(py::init<const std::string&>(), "spec"_a = "")
      .def_property_readonly("name", &ts::Device::name)
      .def_property_readonly("type", &ts::Device::type)
      .def_property_readonly("compile_ms", &ts::Device::compileMs)
      .def("__repr__", [](const ts::Device& d) { return "tileshade.Device('" + d.name() + "')"; });

  py::class_<ts::Camera>(m, "Camera", "The camera a G-buffer was rendered with.")
      .def(py::init<>())
      .def_static("perspective", &ts::Camera::perspective, "width"_a, "height"_a, "yfov"_a,
                  "znear"_a, "zfar"_a)
      .def_readwrite("width", &ts::Camera::width)
      .def_readwrite("height", &ts::Camera::height)
      .def_readwrite("tan_half_fov_x", &ts::Camera::tanHalfFovX)
      .def_readwrite("tan_half_fov_y", &ts::Camera::tanHalfFovY)
      .def_readwrite("znear", &ts::Camera::znear)
      .def_readwrite("zfar", &ts::Camera::zfar)
      .def_readwrite("view_from_world", &ts::Camera::viewFromWorld)
      .def("__repr__", [](const ts::Camera& c) {
        return "tileshade.Camera(" + std::to_string(c.width) + "x" + std::to_string(c.height) +
               ", tan_half_fov=(" + std::to_string(c.tanHalfFovX) + ", " +
               std::to_string(c.tanHalfFovY) + "), znear=" + std::to_string(c.znear) +
               ", zfar=" + std::to_string(c.zfar) + ")";
      });

  py::class_<ts::Light>(m, "Light",
                        "A point, spot or directional light (view space unless the "
                        "camera's view_from_world says otherwise).")
      .def_static("point", &ts::Light::point, "position"_a, "color"_a, "range"_a)
      .def_static("spot", &ts::Light::spot, "position"_a, "direction"_a, "color"_a, "range"_a,
                  "inner_cone_angle"_a, "outer_cone_angle"_a)
      .def_static("directional", &ts::Light::directional, "direction"_a, "color"_a)
      .def_property(
          "type", [](const ts::Light& l) { return lightTypeName(l.type); },
          [](ts::Light& l, const std::string& t) { l.type = lightType(t); })
      .def_readwrite("position", &ts::Light::position)
      .def_readwrite("direction", &ts::Light::direction)
      .def_readwrite("color", &ts::Light::color)
      .def_readwrite("range", &ts::Light::range)
      .def_readwrite("inner_cone_angle", &ts::Light::innerConeAngle)
      .def_readwrite("outer_cone_angle", &ts::Light::outerConeAngle)
      .def("__repr__", [](const ts::Light& l) {
        std::ostringstream s;
        s << "tileshade.Light(" << lightTypeName(l.type) << ", color=(" << l.color[0] << ", "
          << l.color[1] << ", " << l.color[2] << ")";
        if (l.type != ts::LightType::Directional) {
          s << ", position=(" << l.position[0] << ", " << l.position[1] << ", " << l.position[2]
            << "), range=" << l.range;
        }
        s << ")";
        return s.str();
      });

  py::class_<ts::Frame>(m, "Frame", "A G-buffer with its camera and lights, on a device.")
      .def_static(
          "from_scene",
          [](ts::Device& device, const py::kwargs& knobs) {
            ts::SceneRequest request;
            applyKnobs(knobs, &request, nullptr, "Frame.from_scene");
            return frameFromScene(device, request);
          },
          "device"_a, py::keep_alive<0, 1>(),
          "A built-in or glTF scene rasterized; keywords as `tileshade render`'s options "
          "(scene, lights, light_count, width, height, frame, layout, raster, variant, ...).")
      .def_static(
          "from_files",
          [](ts::Device& device, const std::string& path, const std::string& layout) {
            py::gil_scoped_release release;
            return ts::Frame::fromFiles(device, path, layout);
          },
          "device"_a, "path"_a, "layout"_a = "", py::keep_alive<0, 1>(),
          "A G-buffer folder written by `render --dump`, or a descriptor .json.")
      .def_static(
          "from_numpy",
          [](ts::Device& device, py::handle depth, py::handle normal, py::handle diffuse,
             py::handle specular, py::handle emissive, py::handle camera, py::handle lights,
             py::handle ambient, const std::string& layout, const std::string& shadingModel) {
            const auto [width, height] = depthSize(depth);
            return frameFromNumpy(device, {depth, normal, diffuse, specular, emissive},
                                  cameraFrom(camera, width, height), lightsFrom(lights, ambient),
                                  layout, shadingModel);
          },
          "device"_a, "depth"_a, "normal"_a, "diffuse"_a, "specular"_a = py::none(),
          "emissive"_a = py::none(), py::kw_only(), "camera"_a, "lights"_a,
          "ambient"_a = py::none(), "layout"_a = "fp32", "shading_model"_a = "blinn-phong",
          py::keep_alive<0, 1>(),
          "Your own planes (numpy, C order, the layout's dtype: docs/python.md), copied.")
      .def_property_readonly("info", [](const ts::Frame& f) { return frameInfoDict(f.info()); })
      .def("dump", &ts::Frame::dump, "dir"_a, "What `render --dump` writes, into dir.");

  py::class_<ts::ShadeResult>(m, "Result", "One shaded frame: image, kernel times, counters.")
      .def_property_readonly("image", &imageView,
                             "HxWx4 float32, linear RGB + an unused alpha (no copy)")
      .def_readonly("technique", &ts::ShadeResult::technique)
      .def_readonly("width", &ts::ShadeResult::width)
      .def_readonly("height", &ts::ShadeResult::height)
      .def_readonly("total_ms", &ts::ShadeResult::totalMs)
      .def_readonly("lanes", &ts::ShadeResult::lanes)
      .def_readonly("nonfinite_pixels", &ts::ShadeResult::nonfinitePixels)
      .def_readonly("kernel_options", &ts::ShadeResult::kernelOptions)
      .def_property_readonly("kernels",
                             [](const ts::ShadeResult& r) { return kernelsList(r.kernels); })
      .def_property_readonly("counters",
                             [](const ts::ShadeResult& r) { return countersDict(r.counters); })
      .def_property_readonly("check", [](const ts::ShadeResult& r) { return checkDict(r.check); })
      .def("stats", &resultStats, "Everything but the image, as one dict.");

  py::class_<ts::Renderer>(m, "Renderer", "A technique with its knobs on a device.")
      .def(py::init([](ts::Device& device, const std::string& technique, const py::kwargs& knobs) {
             ts::Settings settings;
             settings.technique = technique;
             applyKnobs(knobs, nullptr, &settings, "Renderer");
             return ts::Renderer(device, settings);
           }),
           "device"_a, "technique"_a = "tiled", py::keep_alive<1, 2>())
      .def_property_readonly("settings",
                             [](const ts::Renderer& r) { return settingsDict(r.settings()); })
      .def(
          "prepare",
          [](ts::Renderer& r, const ts::Frame& frame) {
            py::gil_scoped_release release;
            r.prepare(frame);
          },
          "frame"_a, "Builds the kernels for this frame now (never inside a frame's time).")
      .def("shade", &shade, "frame"_a, "check"_a = false,
           "Shades the frame; check=True also compares with the double reference.");

  m.def(
      "render",
      [](const std::string& scene, const std::string& technique, py::handle device, bool check,
         const py::kwargs& knobs) {
        ts::SceneRequest request;
        request.scene = scene;
        ts::Settings settings;
        settings.technique = technique;
        applyKnobs(knobs, &request, &settings, "render");
        ts::Device dev = deviceFrom(device);
        // The renderer first: an unknown technique or knob fails before the scene is rasterized.
        ts::Renderer renderer(dev, settings);
        const ts::Frame frame = frameFromScene(dev, request);
        py::object result = py::cast(shade(renderer, frame, check));
        py::dict stats = resultStats(result.cast<const ts::ShadeResult&>());
        stats["frame"] = frameInfoDict(frame.info());
        stats["device"] = dev.name();
        stats["settings"] = settingsDict(settings);
        // RGB: a view of the result's RGBA image (its alpha is unused).
        py::object rgb = imageView(result)[py::make_tuple(py::ellipsis(), py::slice(0, 3, 1))];
        return py::make_tuple(rgb, stats);
      },
      "scene"_a = "builtin:street", "technique"_a = "tiled", "device"_a = py::none(),
      "check"_a = false,
      "Renders a scene with a technique: (image HxWx3 float32, stats dict). Keywords: the scene's "
      "and the technique's knobs, as `tileshade render`'s options in snake_case.");

  m.def("bench", &bench, "config"_a, "out_dir"_a, "calibrate"_a = false, "quiet"_a = true,
        "`tileshade bench` on a config (a dict, a JSON document or a file): bench.csv's rows as "
        "dicts, numbers as int or float.");
  m.def(
      "bench_dataframe",
      [](py::handle config, const std::string& outDir, bool calibrate, bool quiet) {
        py::module_ pandas;
        try {
          pandas = py::module_::import("pandas");
        } catch (py::error_already_set& e) {
          if (!e.matches(PyExc_ImportError)) throw;
          throw py::import_error(
              "tileshade.bench_dataframe needs pandas (Debian: apt install python3-pandas); "
              "tileshade.bench returns the same rows as a list of dicts");
        }
        return pandas.attr("DataFrame")(bench(config, outDir, calibrate, quiet));
      },
      "config"_a, "out_dir"_a, "calibrate"_a = false, "quiet"_a = true,
      "bench() as a pandas DataFrame (ImportError without pandas).");
}
