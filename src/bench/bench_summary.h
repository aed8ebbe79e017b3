#pragma once
// What `bench` makes of its rows: per-configuration summaries over frames (bench.json
// "summaries", summary.csv) and the table printed at the end of a run.
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

namespace ts {

// Per-configuration summaries (median/min/max over frames) of bench.json-style rows.
nlohmann::json summarizeRows(const nlohmann::json& rows);

// summary.csv: its header (summaryCsvColumns()) and one line per summary.
std::string summaryCsvText(const nlohmann::json& summaries);

// The summaries as an aligned table, with the dimensions that differ between configurations.
void printSummaryTable(const nlohmann::json& summaries, std::ostream& out);

}  // namespace ts
