#pragma once
// The API's results as Python values: dicts with snake_case keys (the names of stats.json and
// bench.csv where those have the value), numpy arrays for images, and bench rows with their
// numbers as numbers.
#include <map>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "tileshade/tileshade.h"

namespace tileshade_python {
namespace py = pybind11;

py::dict deviceDict(const ts::DeviceDescription& device);
py::dict frameInfoDict(const ts::FrameInfo& info);
py::dict errorDict(const ts::ErrorReport& error);
py::object checkDict(const std::optional<ts::CheckReport>& check);  // None without a check
py::list kernelsList(const std::vector<ts::KernelTiming>& kernels);
py::dict countersDict(const ts::Counters& counters);
// Everything of a result but its image.
py::dict resultStats(const ts::ShadeResult& result);

// A bench.csv field: an int or a float where the text is a decimal number (nan and inf too),
// else the text. Columns naming an identifier (config_id, ..._id, ...hash) stay text: a hash of
// digits is no number.
py::object benchValue(const std::string& column, const std::string& text);
// The rows, their columns in bench.csv's order (read from the header of csvPath where it is
// there; else the rows' own, alphabetical).
py::list benchRows(const std::vector<std::map<std::string, std::string>>& rows,
                   const std::string& csvPath);

}  // namespace tileshade_python
