#include "python_knobs.h"

#include <cfloat>
#include <climits>
#include <cmath>
#include <functional>
#include <map>
#include <utility>

namespace tileshade_python {
namespace {

std::string typeName(py::handle value) {
  return py::str(py::type::handle_of(value).attr("__name__"));
}

[[noreturn]] void wrongType(py::handle value, const std::string& name, const std::string& wanted) {
  throw py::type_error(name + ": expected " + wanted + ", got " + typeName(value));
}

bool isInt(py::handle value) {
  // Python ints and numpy's integers (__index__); not bool, an int subclass in Python: True as a
  // tile size is a mistake, not 1.
  return PyIndex_Check(value.ptr()) && !py::isinstance<py::bool_>(value);
}

long long longValue(py::handle value, const std::string& name, long long lo, long long hi) {
  if (!isInt(value)) wrongType(value, name, "an int");
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
  if (overflow != 0 || v < lo || v > hi) {
    throw py::value_error(name + ": " + std::string(py::str(value)) + " is out of range [" +
                          std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return v;
}

// A comma list as the command takes it, or a Python list of its items.
std::string listText(py::handle value, const std::string& name) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    std::string text;
    for (py::handle item : value) {
      if (!text.empty()) text += ",";
      text += textValue(item, name);
    }
    return text;
  }
  wrongType(value, name, "a str or a list of str");
}

// `--lanes auto|1|2|...`, `--shadows none|all|N`: a count as an int, or the option's text.
std::string countOrText(py::handle value, const std::string& name) {
  if (isInt(value)) return std::to_string(longValue(value, name, INT_MIN, INT_MAX));
  return textValue(value, name);
}

// `--shadow-bias C,S`: a (constant, slope) pair of numbers, or the command's text.
std::string biasText(py::handle value, const std::string& name);

// `--tile N|WxH`: an int, a (w, h) pair or the command's text.
std::pair<int, int> tileSize(py::handle value, const std::string& name) {
  if (isInt(value)) {
    const int n = intValue(value, name);
    return {n, n};
  }
  if (py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) {
    const py::sequence seq = py::reinterpret_borrow<py::sequence>(value);
    if (seq.size() != 2)
      throw py::value_error(name + ": expected (width, height), got " + std::to_string(seq.size()) +
                            " values");
    return {intValue(seq[0], name + "[0]"), intValue(seq[1], name + "[1]")};
  }
  if (py::isinstance<py::str>(value)) {
    // Parsed as the command parses it; ts::Error for a bad text, as `--tile 16y8` gives.
    const std::string text = value.cast<std::string>();
    size_t used = 0;
    try {
      const size_t x = text.find('x');
      const int w = std::stoi(text.substr(0, x), &used);
      if (used != (x == std::string::npos ? text.size() : x)) throw std::invalid_argument(text);
      if (x == std::string::npos) return {w, w};
      const int h = std::stoi(text.substr(x + 1), &used);
      if (used != text.size() - x - 1) throw std::invalid_argument(text);
      return {w, h};
    } catch (const std::exception&) {
      throw py::value_error(name + ": '" + text + "' is no tile size (N or WxH)");
    }
  }
  wrongType(value, name, "an int, a (width, height) pair or 'WxH'");
}

using SceneKnob = std::function<void(ts::SceneRequest&, py::handle, const std::string&)>;
using TechniqueKnob = std::function<void(ts::Settings&, py::handle, const std::string&)>;

const std::map<std::string, SceneKnob>& sceneKnobs() {
  using R = ts::SceneRequest;
  static const std::map<std::string, SceneKnob> knobs = {
      {"scene", [](R& r, py::handle v, const std::string& n) { r.scene = textValue(v, n); }},
      {"lights", [](R& r, py::handle v, const std::string& n) { r.lights = textValue(v, n); }},
      {"light_count",
       [](R& r, py::handle v, const std::string& n) { r.lightCount = intValue(v, n); }},
      {"light_range",
       [](R& r, py::handle v, const std::string& n) { r.lightRange = floatValue(v, n); }},
      {"light_threshold",
       [](R& r, py::handle v, const std::string& n) { r.lightThreshold = floatValue(v, n); }},
      {"variant", [](R& r, py::handle v, const std::string& n) { r.variant = listText(v, n); }},
      {"normal_maps",
       [](R& r, py::handle v, const std::string& n) {
         if (!py::isinstance<py::bool_>(v)) wrongType(v, n, "a bool");
         r.normalMaps = v.cast<bool>();
       }},
      {"blend", [](R& r, py::handle v, const std::string& n) { r.blend = textValue(v, n); }},
      {"shadows", [](R& r, py::handle v, const std::string& n) { r.shadows = countOrText(v, n); }},
      {"shadow_map_size",
       [](R& r, py::handle v, const std::string& n) { r.shadowMapSize = intValue(v, n); }},
      {"shadow_budget",
       [](R& r, py::handle v, const std::string& n) { r.shadowBudgetMB = floatValue(v, n); }},
      {"shadow_filter",
       [](R& r, py::handle v, const std::string& n) { r.shadowFilter = textValue(v, n); }},
      {"shadow_bias",
       [](R& r, py::handle v, const std::string& n) { r.shadowBias = biasText(v, n); }},
      {"shading_model",
       [](R& r, py::handle v, const std::string& n) { r.shadingModel = textValue(v, n); }},
      {"features", [](R& r, py::handle v, const std::string& n) { r.features = listText(v, n); }},
      {"seed",
       [](R& r, py::handle v, const std::string& n) {
         r.seed = static_cast<uint32_t>(longValue(v, n, 0, UINT32_MAX));
       }},
      {"width", [](R& r, py::handle v, const std::string& n) { r.width = intValue(v, n); }},
      {"height", [](R& r, py::handle v, const std::string& n) { r.height = intValue(v, n); }},
      {"frame", [](R& r, py::handle v, const std::string& n) { r.frame = intValue(v, n); }},
      {"layout", [](R& r, py::handle v, const std::string& n) { r.layout = textValue(v, n); }},
      {"raster", [](R& r, py::handle v, const std::string& n) { r.raster = textValue(v, n); }},
      {"msaa", [](R& r, py::handle v, const std::string& n) { r.msaa = intValue(v, n); }},
  };
  return knobs;
}

const std::map<std::string, TechniqueKnob>& techniqueKnobs() {
  using S = ts::Settings;
  static const std::map<std::string, TechniqueKnob> knobs = {
      {"technique",
       [](S& s, py::handle v, const std::string& n) { s.technique = textValue(v, n); }},
      {"tile", [](S& s, py::handle v,
                  const std::string& n) { std::tie(s.tileWidth, s.tileHeight) = tileSize(v, n); }},
      {"slices", [](S& s, py::handle v, const std::string& n) { s.slices = intValue(v, n); }},
      {"culling", [](S& s, py::handle v, const std::string& n) { s.culling = textValue(v, n); }},
      {"spot_culling",
       [](S& s, py::handle v, const std::string& n) { s.spotCulling = textValue(v, n); }},
      {"depth_split",
       [](S& s, py::handle v, const std::string& n) {
         if (!py::isinstance<py::bool_>(v)) wrongType(v, n, "a bool");
         s.depthSplit = v.cast<bool>();
       }},
      {"math", [](S& s, py::handle v, const std::string& n) { s.math = textValue(v, n); }},
      {"lanes", [](S& s, py::handle v, const std::string& n) { s.lanes = countOrText(v, n); }},
      {"extra_build_options",
       [](S& s, py::handle v, const std::string& n) { s.extraBuildOptions = textValue(v, n); }},
      {"shadow_storage",
       [](S& s, py::handle v, const std::string& n) { s.shadowStorage = textValue(v, n); }},
  };
  return knobs;
}

template <typename Table>
std::string names(const Table& table) {
  std::string text;
  for (const auto& entry : table) text += (text.empty() ? "" : ", ") + entry.first;
  return text;
}

std::string biasText(py::handle value, const std::string& name) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if ((py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) &&
      py::len(value) == 2) {
    const py::sequence pair = value.cast<py::sequence>();
    // repr of a Python float is its shortest round-trip text: the values as given.
    return std::string(py::repr(py::float_(floatValue(pair[0], name)))) + "," +
           std::string(py::repr(py::float_(floatValue(pair[1], name))));
  }
  wrongType(value, name, "a (constant, slope) pair or 'C,S'");
}

}  // namespace

int intValue(py::handle value, const std::string& name) {
  return static_cast<int>(longValue(value, name, INT_MIN, INT_MAX));
}

float floatValue(py::handle value, const std::string& name) {
  // Anything with __float__ (numpy's scalars too), but no text and no bool.
  if (py::isinstance<py::str>(value) || py::isinstance<py::bool_>(value)) {
    wrongType(value, name, "a number");
  }
  const double v = PyFloat_AsDouble(value.ptr());
  if (v == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    wrongType(value, name, "a number");
  }
  // A double beyond float's range has no float value (the conversion is undefined behaviour).
  if (std::isfinite(v) && std::fabs(v) > double(FLT_MAX)) {
    throw py::value_error(name + ": " + std::string(py::str(value)) + " is beyond float range");
  }
  return static_cast<float>(v);
}

std::string textValue(py::handle value, const std::string& name) {
  if (!py::isinstance<py::str>(value)) wrongType(value, name, "a str");
  return value.cast<std::string>();
}

void applyKnobs(const py::kwargs& kwargs, ts::SceneRequest* scene, ts::Settings* settings,
                const std::string& function) {
  for (const auto& item : kwargs) {
    const std::string name = item.first.cast<std::string>();
    if (scene) {
      const auto it = sceneKnobs().find(name);
      if (it != sceneKnobs().end()) {
        it->second(*scene, item.second, name);
        continue;
      }
    }
    if (settings) {
      const auto it = techniqueKnobs().find(name);
      if (it != techniqueKnobs().end()) {
        it->second(*settings, item.second, name);
        continue;
      }
    }
    std::string known;
    if (scene) known += "scene knobs: " + names(sceneKnobs());
    if (settings)
      known += std::string(scene ? "; " : "") + "technique knobs: " + names(techniqueKnobs());
    throw py::type_error(function + "() got an unexpected keyword argument '" + name + "' (" +
                         known + ")");
  }
}

py::dict settingsDict(const ts::Settings& s) {
  py::dict d;
  d["technique"] = s.technique;
  d["tile"] = py::make_tuple(s.tileWidth, s.tileHeight);
  d["slices"] = s.slices;
  d["culling"] = s.culling;
  d["spot_culling"] = s.spotCulling;
  d["depth_split"] = s.depthSplit;
  d["math"] = s.math;
  d["lanes"] = s.lanes;
  d["extra_build_options"] = s.extraBuildOptions;
  d["shadow_storage"] = s.shadowStorage;
  return d;
}

ts::Device deviceFrom(py::handle device) {
  if (device.is_none()) return ts::Device("");
  if (py::isinstance<py::str>(device)) return ts::Device(device.cast<std::string>());
  if (py::isinstance<ts::Device>(device)) return device.cast<ts::Device>();
  wrongType(device, "device", "None, a device spec str or a tileshade.Device");
}

}  // namespace tileshade_python
