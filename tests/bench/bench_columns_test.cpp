// The bench.csv and summary.csv column tables (src/bench/bench_columns.h): one table drives
// writing a row, reading it back for --resume and the column lists.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_columns.h"
#include "bench/bench_config.h"
#include "bench/bench_stats.h"

namespace {

// A field of every column, each of its type and unlike anything a default run writes.
std::map<std::string, std::string> fabricatedFields() {
  std::map<std::string, std::string> fields;
  int i = 0;
  for (const auto& c : ts::benchColumns()) {
    ++i;
    std::string& v = fields[c.name];
    switch (c.type) {
      case ts::BenchColumnType::Text: v = "text " + std::to_string(i) + ", \"quoted\""; break;
      case ts::BenchColumnType::Integer: v = std::to_string(1000003 * i); break;
      case ts::BenchColumnType::Time: v = ts::numberText(0.125 * i); break;
      case ts::BenchColumnType::Number: v = ts::numberText(-1.5e7 * i); break;
      case ts::BenchColumnType::Kernels: v = "clear=0.25;shade=" + std::to_string(i); break;
      case ts::BenchColumnType::KernelMedians: break;  // summary.csv only
      case ts::BenchColumnType::Notes: v = "first note | second note"; break;
    }
  }
  fields["err_psnr_db"] = "inf";  // an exact image: infinities come back as the string
  fields["err_p50"] = "-inf";
  return fields;
}

std::vector<std::string> inColumnOrder(const std::map<std::string, std::string>& fields) {
  std::vector<std::string> out;
  for (const auto& name : ts::benchCsvColumns()) out.push_back(fields.at(name));
  return out;
}

TEST(BenchColumns, EveryColumnOfAWrittenRowReadsBackTheSame) {
  const auto fields = fabricatedFields();
  for (const auto& c : ts::benchColumns())
    EXPECT_TRUE(ts::wellTyped(c, fields.at(c.name))) << c.name << " = " << fields.at(c.name);
  nlohmann::json row = ts::rowFromCsv(fields, "fabricated.csv");
  // Every column has its value at its path, of its JSON type.
  for (const auto& c : ts::benchColumns()) {
    nlohmann::json::json_pointer path(c.path);
    ASSERT_TRUE(row.contains(path)) << c.name << " at " << c.path;
    const nlohmann::json& v = row.at(path);
    switch (c.type) {
      case ts::BenchColumnType::Text: EXPECT_EQ(v, fields.at(c.name)) << c.name; break;
      case ts::BenchColumnType::Integer:
        EXPECT_EQ(v.dump(), fields.at(c.name)) << c.name;
        EXPECT_TRUE(v.is_number_integer()) << c.name;
        break;
      case ts::BenchColumnType::Time:
      case ts::BenchColumnType::Number:
        EXPECT_TRUE(v.is_number() || v == "inf" || v == "-inf") << c.name << " = " << v;
        break;
      case ts::BenchColumnType::Kernels: EXPECT_EQ(v.size(), 2u) << c.name; break;
      case ts::BenchColumnType::KernelMedians: ADD_FAILURE() << c.name << " in bench.csv"; break;
      case ts::BenchColumnType::Notes:
        EXPECT_EQ(v, (nlohmann::json{"first note", "second note"})) << c.name;
        break;
    }
  }
  EXPECT_EQ(row["technique"], fields.at("technique"));  // techniqueJson's own key
  // Written again, every field is what it was; read again, the row is what it was.
  const std::vector<std::string> written = ts::csvFields(ts::benchColumns(), row);
  EXPECT_EQ(written, inColumnOrder(fields));
  std::map<std::string, std::string> again;
  for (size_t i = 0; i < written.size(); ++i) again[ts::benchCsvColumns()[i]] = written[i];
  EXPECT_EQ(ts::rowFromCsv(again, "fabricated.csv"), row);
  // And through a CSV line (the quoting of text fields) too.
  std::vector<std::string> parsed;
  ASSERT_TRUE(ts::parseCsvRecord(ts::csvLine(written), parsed));
  EXPECT_EQ(parsed, written);
}

TEST(BenchColumns, OptionalValuesAndGroupsComeBackOnlyWhenWritten) {
  auto fields = fabricatedFields();
  for (const auto& c : ts::benchColumns())
    if (!c.required && c.presentIf.empty()) fields[c.name] = "";
  fields["reference_contributing"] = "";
  fields["err_max_abs"] = "";  // the group's first: no error object, whatever the others hold
  fields["err_shading_max_rel_peak"] = "";
  nlohmann::json row = ts::rowFromCsv(fields, "fabricated.csv");
  EXPECT_FALSE(row.contains("reference_contributing"));
  EXPECT_FALSE(row.contains("error"));
  EXPECT_FALSE(row.contains("error_shading"));
  EXPECT_TRUE(row["limit"]["limit_ms"].is_null());  // always there, null when empty
  EXPECT_EQ(row["notes"], nlohmann::json::array());
  for (const auto& c : ts::benchColumns())
    EXPECT_TRUE(!c.required || !ts::wellTyped(c, "")) << c.name;
  for (const auto& c : ts::benchColumns()) {
    if (c.type != ts::BenchColumnType::Integer) continue;
    EXPECT_FALSE(ts::wellTyped(c, "12.5")) << c.name;
    EXPECT_FALSE(ts::wellTyped(c, "1234567890123456789")) << c.name;  // 19 digits
  }
}

bool inTable(const std::vector<ts::BenchColumn>& table, const std::string& name) {
  return std::any_of(table.begin(), table.end(),
                     [&](const ts::BenchColumn& c) { return c.name == name; });
}

TEST(BenchColumns, TablesNameEveryDimensionOnceAndEveryColumnHasAPath) {
  for (const auto* table : {&ts::benchColumns(), &ts::summaryColumns()}) {
    std::set<std::string> names;
    for (const auto& c : *table) {
      EXPECT_TRUE(names.insert(c.name).second) << c.name;
      EXPECT_EQ(c.path.rfind('/', 0), 0u) << c.name << ": " << c.path;
      EXPECT_TRUE(c.presentIf.empty() || inTable(*table, c.presentIf))
          << c.name << " present if " << c.presentIf;
    }
    for (const auto& d : ts::benchDimensions()) EXPECT_TRUE(names.count(d.name)) << d.name;
  }
  EXPECT_EQ(ts::benchCsvColumns().front(), "config_id");
  EXPECT_EQ(ts::summaryCsvColumns().front(), "config_id");
}

}  // namespace
