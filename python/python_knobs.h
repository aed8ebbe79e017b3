#pragma once
// Keyword arguments of the Python functions as the API's requests: scene knobs (ts::SceneRequest)
// and technique knobs (ts::Settings), by the names `tileshade render` takes, in snake_case
// (light_count for --light-count). Python checks the types here (a TypeError naming the knob);
// the values themselves are the API's to check (ts::Error, the command's one-line messages).
#include <string>

#include <pybind11/pybind11.h>

#include "tileshade/tileshade.h"

namespace tileshade_python {
namespace py = pybind11;

// Applies every keyword to `scene` or `settings` (either may be null: its knobs are then unknown
// to the caller). An unknown keyword is a TypeError naming it and the knobs `function` takes.
void applyKnobs(const py::kwargs& kwargs, ts::SceneRequest* scene, ts::Settings* settings,
                const std::string& function);

// A technique's knobs back as keywords (Renderer.settings).
py::dict settingsDict(const ts::Settings& settings);

// None (the default device: first GPU, else CPU, $TILESHADE_DEVICE when set), a `--device` spec
// string, or a tileshade.Device.
ts::Device deviceFrom(py::handle device);

// Type checks with the knob's name in the message (TypeError), for the other modules too.
int intValue(py::handle value, const std::string& name);
float floatValue(py::handle value, const std::string& name);
std::string textValue(py::handle value, const std::string& name);

}  // namespace tileshade_python
