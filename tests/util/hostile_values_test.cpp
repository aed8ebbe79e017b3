// Hostile values for the shared helpers (issue #12): the option validators refuse NaN, inf and
// values out of range, and every write reports a full disk or a path through a file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.h"
#include "util/error.h"
#include "util/file_write.h"
#include "util/option_values.h"

namespace fs = std::filesystem;

namespace {

// A fresh folder per test (CTest runs tests in parallel processes).
fs::path freshDir(const std::string& name) { return ts::test::freshDir("hostile", name); }

TEST(HostileOptions, SharedValidatorsRefuseNanInfAndRanges) {
  using ts::NumberRule;
  for (const char* bad : {"nan", "inf", "-inf", "-1", "1e39", "abc", "", "1.5x"})
    EXPECT_THROW(ts::parseNumber("--x", bad, NumberRule::AtLeastZero), ts::Error) << bad;
  EXPECT_EQ(ts::parseNumber("--x", " 0.25 ", NumberRule::AtLeastZero), 0.25f);
  EXPECT_THROW(ts::parseNumber("--x", "0", NumberRule::AboveZero), ts::Error);
  EXPECT_THROW(ts::checkNumber("--x", std::nan(""), NumberRule::AtLeastZero), ts::Error);
  EXPECT_THROW(ts::parseInteger("--n", "99999999999999999999", 0, 10), ts::Error);
  try {
    ts::checkNumber("--exposure", -1.0, NumberRule::AboveZero);
    ADD_FAILURE();
  } catch (const ts::Error& e) {
    EXPECT_EQ(std::string(e.what()), "--exposure: expected a finite number > 0, got '-1'");
  }
}

TEST(HostileWrites, WriteFileReportsAFullDisk) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  try {
    ts::writeFile("/dev/full", std::string(100000, 'x'));
    ADD_FAILURE() << "no error writing /dev/full";
  } catch (const ts::Error& e) {
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  std::ofstream stream("/dev/full");
  stream << std::string(100000, 'x');
  EXPECT_THROW(ts::flushChecked(stream, "/dev/full"), ts::Error);
  fs::path dir = freshDir("write_into_file");
  std::ofstream(dir / "file") << "x";
  EXPECT_THROW(ts::writeFile((dir / "file" / "stats.json").string(), "{}"), ts::Error);
  fs::remove_all(dir);
}

}  // namespace
