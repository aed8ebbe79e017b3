// The hard-case suite (`tileshade check`, src/check/) as CTest cases with the label `check`: one
// GoogleTest case per hard case, each through every technique, G-buffer layout and lanes 1 and 16
// (the case may add widths), against the double reference within the fp32 bound, with no NaN/inf
// and no missed light. A failure prints the case's table. Also the command itself.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "check/check_run.h"
#include "check/hard_cases.h"
#include "test_support.h"

namespace ts {
namespace {

class HardCaseTest : public ::testing::TestWithParam<std::string> {};

TEST_P(HardCaseTest, EveryTechniqueLayoutAndLanesWithinFp32) {
  CheckOptions o;
  o.cases = {GetParam()};
  o.device = std::getenv("TILESHADE_DEVICE") ? "" : "cpu";
  std::ostringstream table;
  std::vector<CheckRow> rows = runHardCases(o, table);
  ASSERT_FALSE(rows.empty());
  size_t failed = 0;
  for (const auto& r : rows) failed += !r.pass();
  EXPECT_EQ(failed, 0u) << table.str();
}

std::vector<std::string> caseNames() {
  std::vector<std::string> names;
  for (const auto& c : hardCases()) names.push_back(c.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Check, HardCaseTest, ::testing::ValuesIn(caseNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string n = info.param;
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

using test::CliRun;
using test::runTileshade;

TEST(CheckCommand, PrintsTheTableAndFailsOnBadInputWithOneLine) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade binary not built";
  CliRun ok =
      runTileshade("check --case resolution-1x1 --technique brute --gbuffer fp16 --device cpu");
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_NE(ok.output.find("max err/peak"), std::string::npos) << ok.output;
  EXPECT_NE(ok.output.find("resolution-1x1                brute             fp16"),
            std::string::npos)
      << ok.output;
  EXPECT_NE(ok.output.find("all 2 hard-case runs passed"), std::string::npos) << ok.output;
  CliRun list = runTileshade("check --list");
  EXPECT_EQ(list.status, 0);
  for (const auto& c : hardCases()) EXPECT_NE(list.output.find(c.name), std::string::npos);
  for (const char* bad :
       {"check --case no-such-case", "check --technique nonsense", "check --gbuffer fp8"}) {
    CliRun r = runTileshade(std::string(bad) + " --device cpu");
    EXPECT_NE(r.status, 0) << bad;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << bad << ": " << r.output;
    EXPECT_EQ(r.output.rfind("tileshade: error: ", 0), 0u) << bad << ": " << r.output;
  }
}

}  // namespace
}  // namespace ts
