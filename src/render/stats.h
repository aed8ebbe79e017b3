#pragma once
// JSON records shared by `render` (stats.json) and `bench`; field names are a public interface
// documented in docs/output-formats.md.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "reference/error_metrics.h"
#include "techniques/technique.h"

namespace ts {

nlohmann::json errorJson(const ErrorStats& e);

// One technique's frame: kernels, totals, counters and, when given, error and missed lights.
nlohmann::json techniqueJson(const std::string& name, const FrameResult& r,
                             const std::optional<ErrorStats>& error,
                             const std::optional<uint64_t>& missed);

}  // namespace ts
