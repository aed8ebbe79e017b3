#pragma once
// Python values as a frame's inputs: numpy G-buffer planes (dtype, shape and C order checked,
// a ValueError naming the plane), the camera (a tileshade.Camera or a dict) and the lights
// (tileshade.Light objects or dicts in the form of lights.json, docs/output-formats.md).
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "tileshade/tileshade.h"

namespace tileshade_python {
namespace py = pybind11;

// A Camera, or a dict {"yfov": radians} or {"tan_half_fov": [x, y]} with optional "znear",
// "zfar", "view_from_world" (16 floats column-major, or a 4x4 matrix as rows) and "width",
// "height" (default: the planes' size).
ts::Camera cameraFrom(py::handle camera, int width, int height);

// A Light, or a dict {"type": "point"|"spot"|"directional", "position", "direction", "color",
// "range", "inner_cone_angle", "outer_cone_angle"}: the keys its type uses, no others.
ts::Light lightFrom(py::handle light, const std::string& name);
// lights: a list of those; ambient: 3 floats.
ts::Lights lightsFrom(py::handle lights, py::handle ambient);

struct NumpyPlanes {
  py::handle depth, normal, diffuse, specular, emissive;  // specular, emissive may be None
};

// Frame::fromHost over the arrays (copied by it). Per layout: depth HxW float32; "fp32" the others
// HxWx4 float32; "fp16" HxWx4 float16; "packed" normal, diffuse, specular HxW uint32 (the
// metallic-roughness specular HxW uint8), emissive HxWx4 float16.
ts::Frame frameFromNumpy(ts::Device& device, const NumpyPlanes& planes, const ts::Camera& camera,
                         const ts::Lights& lights, const std::string& layout,
                         const std::string& shadingModel);

// The size of the depth plane (checked as float32 HxW), for a camera dict without one.
std::pair<int, int> depthSize(py::handle depth);

}  // namespace tileshade_python
