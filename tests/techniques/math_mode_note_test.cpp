// mathModeNote (src/techniques/math_mode_note.h): the one-line note `render` and `bench` print for
// a
// --math setting that buys nothing on the device (issue #19).
#include <gtest/gtest.h>

#include "techniques/math_mode_note.h"

namespace ts {
namespace {

const char* kPocl = "Portable Computing Language / pthread-skylake-avx512-Intel(R) Xeon(R)";

TEST(MathModeNote, NativeOnPoclCpuSaysItIsPrecise) {
  std::string note = mathModeNote(MathMode::Native, kPocl, "cpu");
  EXPECT_NE(note.find("--math native"), std::string::npos) << note;
  EXPECT_NE(note.find("same machine code as precise"), std::string::npos) << note;
  EXPECT_EQ(note.find('\n'), std::string::npos) << "one line";
}

TEST(MathModeNote, FastOnPoclCpuSaysItIsNoFaster) {
  std::string note = mathModeNote(MathMode::Fast, kPocl, "cpu");
  EXPECT_NE(note.find("--math fast: not measurably faster than precise"), std::string::npos)
      << note;
  EXPECT_EQ(note.find('\n'), std::string::npos) << "one line";
}

TEST(MathModeNote, PreciseNeverHasANote) {
  EXPECT_EQ(mathModeNote(MathMode::Precise, kPocl, "cpu"), "");
  EXPECT_EQ(mathModeNote(MathMode::Precise, "NVIDIA CUDA / NVIDIA H200", "gpu"), "");
}

TEST(MathModeNote, OtherDevicesKeepTheirNativeFunctions) {
  EXPECT_EQ(mathModeNote(MathMode::Native, "NVIDIA CUDA / NVIDIA H200", "gpu"), "");
  EXPECT_EQ(mathModeNote(MathMode::Native, "Oclgrind / Oclgrind Simulator", "other"), "");
  EXPECT_EQ(mathModeNote(MathMode::Fast, "NVIDIA CUDA / NVIDIA H200", "gpu"), "");
}

}  // namespace
}  // namespace ts
