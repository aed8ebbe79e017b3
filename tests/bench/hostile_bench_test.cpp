// Hostile bench input in-process (issue #12): configs with absurd values and the fuzzer's
// findings are one-line errors, summaries keep infinite errors, --quiet never hides a failure.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/bench_cli.h"
#include "bench/bench_config.h"
#include "bench/bench_run.h"
#include "bench/bench_stats.h"
#include "util/progress.h"
#include "test_support.h"
#include "util/error.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

TEST(HostileStats, BenchSummariesKeepInfiniteErrors) {
  auto row = [](int frame, json error) {
    return json{{"config_id", "c"},         {"config", {{"technique", "tiled"}}},
                {"technique", "tiled"},     {"frame", frame},
                {"total_ms", 1.0},          {"error", error},
                {"nonfinite_pixels", frame}};
  };
  json rows = json::array(
      {row(0, {{"max_abs", 0.0}, {"rmse", 0.0}, {"psnr_db", "inf"}, {"max_rel_peak", 0.0}}),
       row(1,
           {{"max_abs", "inf"}, {"rmse", "inf"}, {"psnr_db", "-inf"}, {"max_rel_peak", "inf"}})});
  json s = ts::summarizeRows(rows);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0]["error"]["psnr_db"], "-inf");  // not "inf" (exact), not the finite frame's
  EXPECT_EQ(s[0]["error"]["max_abs"], "inf");
  EXPECT_EQ(s[0]["nonfinite_pixels_max"], 1);
  json exact = ts::summarizeRows(json::array({rows[0]}));
  EXPECT_EQ(exact[0]["error"]["psnr_db"], "inf");
}

void expectConfigError(const std::string& text, const std::string& needle) {
  ts::BenchOptions o;
  try {
    ts::applyBenchConfig(text, "c.json", o, [](const std::string&) { return false; });
    ts::expandSweep(o.sweep);
    ADD_FAILURE() << "no error for " << text;
  } catch (const ts::Error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(needle), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(HostileBenchConfig, AbsurdValuesAreOneLineErrors) {
  expectConfigError(R"({"calib_mib": -1})", "calib_mib");    // was shifted into a huge size_t
  expectConfigError(R"({"warmup": 4294967297})", "warmup");  // was truncated to 1
  expectConfigError(R"({"repeat": 0})", "repeat");
  expectConfigError(R"({"frames": 1e30})", "frames");
  expectConfigError(R"({"light_threshold": "nan"})", "--light-threshold");
  expectConfigError(R"({"light_range": 1e39})", "--light-range");
  expectConfigError(R"({"slices": 0})", "--slices");
  // A product of lists far beyond what could run: refused before it is built.
  std::string many;
  for (int i = 1; i <= 60; ++i) many += (i > 1 ? "," : "") + std::to_string(i);
  expectConfigError(R"({"seed": [)" + many + R"(], "light_count": [)" + many + R"(], "tile": [)" +
                        many + R"(], "slices": [)" + many + "]}",
                    "configurations");
  // Repeated values do not multiply: 1000 copies of one tile size are one configuration.
  ts::BenchOptions o;
  std::string same;
  for (int i = 0; i < 1000; ++i) same += std::string(i ? "," : "") + "\"16\"";
  ts::applyBenchConfig(R"({"tile": [)" + same + R"(], "seed": [)" + same + "]}", "c.json", o,
                       [](const std::string&) { return false; });
  EXPECT_EQ(ts::expandSweep(o.sweep).size(), 1u);
}

// Bench configs the fuzzer found slow or crashing (tests/data/fuzz/*.json): each is applied and
// expanded, ending in success or one line.
TEST(HostileBenchConfig, FuzzerFindingsParseOrFailCleanly) {
  fs::path dir = fs::path(ts::test::sourceDir()) / "tests" / "data" / "fuzz";
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".json") continue;
    ++files;
    std::ifstream in(e.path());
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ts::BenchOptions o;
    try {
      ts::applyBenchConfig(text, e.path().string(), o, [](const std::string&) { return false; });
      ts::expandSweep(o.sweep);
    } catch (const ts::Error& x) {
      EXPECT_EQ(std::string(x.what()).find('\n'), std::string::npos) << x.what();
    }
  }
  EXPECT_GT(files, 0u);
}

TEST(HostileBenchMessages, QuietNeverHidesAFailure) {
  ::testing::internal::CaptureStderr();
  {
    ts::Progress quiet(3, false);
    quiet.step("a");
    quiet.note("bench: configuration failed: why");
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "bench: configuration failed: why\n");
}

}  // namespace
