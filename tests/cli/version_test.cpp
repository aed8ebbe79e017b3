// `tileshade --version` prints the version CMake's project() sets (through tileshade/version.h).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "test_support.h"
#include "tileshade/version.h"

TEST(Version, FlagPrintsOneLineAndSucceeds) {
  const ts::test::CliRun r = ts::test::runTileshade("--version");
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_EQ(r.output, std::string("tileshade ") + TILESHADE_VERSION + "\n");
}

TEST(Version, FlagNeedsNoSubcommandAndWinsOverOne) {
  // A subcommand is otherwise required; --version before one still only prints the version.
  const ts::test::CliRun r = ts::test::runTileshade("--version render --width 0");
  EXPECT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_EQ(r.output, std::string("tileshade ") + TILESHADE_VERSION + "\n");
}

TEST(Version, HelpNamesTheFlag) {
  const ts::test::CliRun r = ts::test::runTileshade("--help");
  EXPECT_EQ(r.exitCode(), 0);
  EXPECT_NE(r.output.find("--version"), std::string::npos) << r.output;
}
