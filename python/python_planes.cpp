#include "python_planes.h"

#include <cstdint>
#include <map>
#include <set>

#include "python_knobs.h"

namespace tileshade_python {
namespace {

const std::string kFunction = "Frame.from_numpy: ";

std::string typeName(py::handle value) {
  return py::str(py::type::handle_of(value).attr("__name__"));
}

std::string dtypeName(const py::dtype& dtype) { return dtype.attr("name").cast<std::string>(); }

std::string shapeText(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) text += (i ? ", " : "") + std::to_string(a.shape(i));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

std::string shapeText(int height, int width, int channels) {
  return "(" + std::to_string(height) + ", " + std::to_string(width) +
         (channels ? ", " + std::to_string(channels) : "") + ")";
}

// One plane's array as the layout stores it: exactly `dtype` (no conversion: a float64 array is a
// mistake the caller should see, and a silent copy would hide its cost), C order, and the shape
// (channels 0: HxW). Returns its data.
const void* checkedPlane(py::handle value, const std::string& name, const py::dtype& dtype,
                         int height, int width, int channels, const std::string& layout) {
  const std::string wanted = dtypeName(dtype) + " array of shape " +
                             shapeText(height, width, channels) + " (layout " + layout + ")";
  if (!py::isinstance<py::array>(value)) {
    throw py::value_error(kFunction + name + ": expected a numpy " + wanted + ", got " +
                          typeName(value));
  }
  const auto a = py::reinterpret_borrow<py::array>(value);
  const bool shapeOk = a.ndim() == (channels ? 3 : 2) && a.shape(0) == height &&
                       a.shape(1) == width && (!channels || a.shape(2) == channels);
  if (!a.dtype().equal(dtype) || !shapeOk) {
    throw py::value_error(kFunction + name + ": expected a " + wanted + ", got " +
                          dtypeName(a.dtype()) + " of shape " + shapeText(a));
  }
  if (!(a.flags() & py::array::c_style)) {
    throw py::value_error(kFunction + name +
                          ": the array is not C-contiguous (numpy.ascontiguousarray makes it so)");
  }
  return a.data();
}

ts::Float3 float3Value(py::handle value, const std::string& name) {
  if (py::isinstance<py::str>(value) || !py::isinstance<py::sequence>(value)) {
    throw py::type_error(name + ": expected 3 numbers, got " + typeName(value));
  }
  const auto seq = py::reinterpret_borrow<py::sequence>(value);
  if (seq.size() != 3) {
    throw py::value_error(name + ": expected 3 numbers, got " + std::to_string(seq.size()));
  }
  return {floatValue(seq[0], name + "[0]"), floatValue(seq[1], name + "[1]"),
          floatValue(seq[2], name + "[2]")};
}

// A dict's entries by key, each taken once; the keys left over are an error naming the first.
class DictReader {
 public:
  DictReader(py::handle value, std::string name) : name_(std::move(name)) {
    if (!py::isinstance<py::dict>(value)) {
      throw py::type_error(name_ + ": expected a dict, got " + typeName(value));
    }
    for (const auto& item : py::reinterpret_borrow<py::dict>(value)) {
      entries_.emplace(textValue(item.first, name_ + " key"), item.second);
    }
  }
  bool has(const std::string& key) const { return entries_.count(key) != 0; }
  py::handle take(const std::string& key) {
    const auto it = entries_.find(key);
    if (it == entries_.end()) throw py::value_error(name_ + ": '" + key + "' is missing");
    const py::handle value = it->second;
    entries_.erase(it);
    return value;
  }
  // Every key one of `keys`, before any is read: a typo is named, not reported as a key missing.
  void only(const std::set<std::string>& keys) const {
    for (const auto& e : entries_) {
      if (!keys.count(e.first)) {
        std::string known;
        for (const auto& k : keys) known += (known.empty() ? "" : ", ") + k;
        throw py::value_error(name_ + ": unknown key '" + e.first + "' (keys: " + known + ")");
      }
    }
  }
  // Every key taken; `context` says what the leftovers do not apply to.
  void finish(const std::string& context) const {
    if (entries_.empty()) return;
    std::string keys;
    for (const auto& e : entries_) keys += (keys.empty() ? "'" : ", '") + e.first + "'";
    throw py::value_error(name_ + ": unknown key " + keys + " " + context);
  }

 private:
  std::string name_;
  std::map<std::string, py::handle> entries_;
};

// "view_from_world": 16 floats column-major (as ts::Camera), or a 4x4 matrix as rows (numpy's
// M[row][col], as matrices are written).
std::array<float, 16> matrixValue(py::handle value, const std::string& name) {
  if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value)) {
    throw py::type_error(name + ": expected 16 numbers or a 4x4 matrix, got " + typeName(value));
  }
  const auto seq = py::reinterpret_borrow<py::sequence>(value);
  std::array<float, 16> m{};
  if (seq.size() == 16) {
    for (size_t i = 0; i < 16; ++i) m[i] = floatValue(seq[i], name + "[" + std::to_string(i) + "]");
    return m;
  }
  if (seq.size() == 4) {
    for (size_t row = 0; row < 4; ++row) {
      const std::string rowName = name + "[" + std::to_string(row) + "]";
      py::handle r = seq[row];
      if (!py::isinstance<py::sequence>(r) || py::len(r) != 4) {
        throw py::value_error(rowName + ": expected a row of 4 numbers");
      }
      const auto rs = py::reinterpret_borrow<py::sequence>(r);
      for (size_t col = 0; col < 4; ++col) {
        m[col * 4 + row] = floatValue(rs[col], rowName + "[" + std::to_string(col) + "]");
      }
    }
    return m;
  }
  throw py::value_error(name + ": expected 16 numbers or a 4x4 matrix, got " +
                        std::to_string(seq.size()) + " values");
}

}  // namespace

std::pair<int, int> depthSize(py::handle depth) {
  if (!py::isinstance<py::array>(depth)) {
    throw py::value_error(kFunction +
                          "depth: expected a numpy float32 array of shape (H, W), got " +
                          typeName(depth));
  }
  const auto a = py::reinterpret_borrow<py::array>(depth);
  if (a.ndim() != 2 || !a.dtype().equal(py::dtype::of<float>())) {
    throw py::value_error(kFunction + "depth: expected a float32 array of shape (H, W), got " +
                          dtypeName(a.dtype()) + " of shape " + shapeText(a));
  }
  return {static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0))};
}

ts::Camera cameraFrom(py::handle camera, int width, int height) {
  if (py::isinstance<ts::Camera>(camera)) return camera.cast<ts::Camera>();
  DictReader d(camera, "camera");
  d.only({"width", "height", "yfov", "tan_half_fov", "znear", "zfar", "view_from_world"});
  const int w = d.has("width") ? intValue(d.take("width"), "camera width") : width;
  const int h = d.has("height") ? intValue(d.take("height"), "camera height") : height;
  const float znear = d.has("znear") ? floatValue(d.take("znear"), "camera znear") : 0.1f;
  const float zfar = d.has("zfar") ? floatValue(d.take("zfar"), "camera zfar") : 1000.0f;
  ts::Camera c;
  if (d.has("yfov") == d.has("tan_half_fov")) {
    throw py::value_error(
        "camera: give exactly one of 'yfov' (radians) and 'tan_half_fov' ([x, y])");
  }
  if (d.has("yfov")) {
    c = ts::Camera::perspective(w, h, floatValue(d.take("yfov"), "camera yfov"), znear, zfar);
  } else {
    const py::handle t = d.take("tan_half_fov");
    if (!py::isinstance<py::sequence>(t) || py::len(t) != 2) {
      throw py::value_error("camera tan_half_fov: expected [tan x, tan y]");
    }
    const auto seq = py::reinterpret_borrow<py::sequence>(t);
    c.width = w;
    c.height = h;
    c.tanHalfFovX = floatValue(seq[0], "camera tan_half_fov[0]");
    c.tanHalfFovY = floatValue(seq[1], "camera tan_half_fov[1]");
    c.znear = znear;
    c.zfar = zfar;
  }
  if (d.has("view_from_world")) {
    c.viewFromWorld = matrixValue(d.take("view_from_world"), "camera view_from_world");
  }
  return c;
}

ts::Light lightFrom(py::handle light, const std::string& name) {
  if (py::isinstance<ts::Light>(light)) return light.cast<ts::Light>();
  DictReader d(light, name);
  d.only(
      {"type", "position", "direction", "color", "range", "inner_cone_angle", "outer_cone_angle"});
  const std::string type = textValue(d.take("type"), name + " type");
  const auto f3 = [&](const char* key) { return float3Value(d.take(key), name + " " + key); };
  const auto f = [&](const char* key) { return floatValue(d.take(key), name + " " + key); };
  ts::Light l;
  if (type == "point") {
    const ts::Float3 position = f3("position"), color = f3("color");
    l = ts::Light::point(position, color, f("range"));
  } else if (type == "spot") {
    const ts::Float3 position = f3("position"), direction = f3("direction"), color = f3("color");
    const float range = f("range");
    const float inner = d.has("inner_cone_angle") ? f("inner_cone_angle") : 0.0f;
    l = ts::Light::spot(position, direction, color, range, inner, f("outer_cone_angle"));
  } else if (type == "directional") {
    const ts::Float3 direction = f3("direction"), color = f3("color");
    l = ts::Light::directional(direction, color);
  } else {
    throw py::value_error(name + " type: '" + type + "' is none of point, spot, directional");
  }
  d.finish("for a " + type + " light");
  return l;
}

ts::Lights lightsFrom(py::handle lights, py::handle ambient) {
  if (py::isinstance<py::str>(lights) || py::isinstance<py::dict>(lights) ||
      !py::isinstance<py::sequence>(lights)) {
    throw py::type_error("lights: expected a list of tileshade.Light or dicts, got " +
                         typeName(lights));
  }
  ts::Lights out;
  size_t i = 0;
  for (py::handle light : lights)
    out.lights.push_back(lightFrom(light, "light " + std::to_string(i++)));
  if (!ambient.is_none()) out.ambient = float3Value(ambient, "ambient");
  return out;
}

ts::Frame frameFromNumpy(ts::Device& device, const NumpyPlanes& planes, const ts::Camera& camera,
                         const ts::Lights& lights, const std::string& layout,
                         const std::string& shadingModel) {
  if (layout != "fp32" && layout != "fp16" && layout != "packed") {
    // Before the planes' dtypes, which depend on it.
    throw py::value_error(kFunction + "layout: '" + layout + "' is none of fp32, fp16, packed");
  }
  const auto [width, height] = depthSize(planes.depth);
  ts::HostGBuffer g;
  g.width = width;
  g.height = height;
  g.layout = layout;
  g.shadingModel = shadingModel;
  const py::dtype f32 = py::dtype::of<float>(), f16("float16"), u32 = py::dtype::of<uint32_t>(),
                  u8 = py::dtype::of<uint8_t>();
  g.depth =
      static_cast<const float*>(checkedPlane(planes.depth, "depth", f32, height, width, 0, layout));
  // What each plane is per layout (tileshade.h, HostGBuffer); an unknown layout is the API's error.
  struct Element {
    py::dtype dtype;
    int channels;
  };
  Element colour{f32, 4}, spec{f32, 4}, emis{f32, 4};
  if (layout == "fp16") {
    colour = spec = emis = {f16, 4};
  } else if (layout == "packed") {
    colour = {u32, 0};
    spec = {shadingModel == "metallic-roughness" ? u8 : u32, 0};
    emis = {f16, 4};
  }
  g.normal =
      checkedPlane(planes.normal, "normal", colour.dtype, height, width, colour.channels, layout);
  g.diffuse =
      checkedPlane(planes.diffuse, "diffuse", colour.dtype, height, width, colour.channels, layout);
  if (!planes.specular.is_none()) {
    g.specular =
        checkedPlane(planes.specular, "specular", spec.dtype, height, width, spec.channels, layout);
  }
  if (!planes.emissive.is_none()) {
    g.emissive =
        checkedPlane(planes.emissive, "emissive", emis.dtype, height, width, emis.channels, layout);
  }
  // The planes are the caller's memory until fromHost has copied them: the Python objects stay
  // referenced by the caller's frame of the call, and the GIL is kept so no one mutates them.
  return ts::Frame::fromHost(device, g, camera, lights);
}

}  // namespace tileshade_python
