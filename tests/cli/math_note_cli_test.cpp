// `render --math native` on PoCL says, in one note line, that the setting compiles to precise's
// code there (issue #19; src/techniques/math_mode_note.h); precise prints no such note.
#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.h"

namespace {

using ts::test::CliRun;
using ts::test::runTileshade;

CliRun renderWithMath(const std::string& math) {
  std::string dir = ts::test::freshDir("math_note", math).string();
  return runTileshade("render --width 64 --height 36 --technique tiled --math " + math + " --out " +
                      dir);
}

TEST(MathNoteCli, NativeOnPoclSaysSameCodeAsPrecise) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade not built";
  CliRun r = renderWithMath("native");
  ASSERT_EQ(r.exitCode(), 0) << r.output;
  bool pocl = r.output.find("Portable Computing Language") != std::string::npos;
  bool noted = r.output.find("tileshade: note: --math native: the same machine code as precise") !=
               std::string::npos;
  EXPECT_EQ(noted, pocl) << r.output;
}

TEST(MathNoteCli, PreciseHasNoMathNote) {
  if (!std::filesystem::exists(TILESHADE_BINARY)) GTEST_SKIP() << "tileshade not built";
  CliRun r = renderWithMath("precise");
  ASSERT_EQ(r.exitCode(), 0) << r.output;
  EXPECT_EQ(r.output.find("note: --math"), std::string::npos) << r.output;
}

}  // namespace
