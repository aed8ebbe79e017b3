#pragma once
// JSON records shared by `render` (stats.json) and `bench`; field names are a public interface
// documented in docs/output-formats.md.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "reference/error_metrics.h"
#include "techniques/technique.h"

namespace ts {

// A number for JSON: finite values as numbers, infinities and NaN as the strings "inf", "-inf",
// "nan" (nlohmann would write null, which reads as "no value").
nlohmann::json jsonNumber(double v);

nlohmann::json errorJson(const ErrorStats& e);

// One technique's frame: kernels, totals, counters, the count of NaN/inf pixels and, when given,
// error and missed lights.
nlohmann::json techniqueJson(const std::string& name, const FrameResult& r,
                             const std::optional<ErrorStats>& error,
                             const std::optional<uint64_t>& missed);

}  // namespace ts
