#pragma once
// The JSON readers' one-line errors in the tests (json_input_test.cpp, strict_json_test.cpp): a
// call's ts::Error message, and that a message is one short line holding what it must.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "util/error.h"
#include "util/strict_json.h"

namespace ts::test {

// An error line this long or longer echoes too much of its input.
inline constexpr size_t kShortLine = 600;

inline void writeText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

inline std::string readText(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

inline std::string nested(size_t depth) {
  return std::string(depth, '[') + std::string(depth, ']');
}

// ts::Error's message from f(), "" when it did not throw.
template <typename F>
std::string errorOf(F&& f) {
  try {
    f();
  } catch (const ts::Error& e) {
    return e.what();
  }
  return "";
}

// parseStrictJson's message ("" when it parses), source "src".
inline std::string errorOfParse(const std::string& text) {
  return errorOf([&] { ts::parseStrictJson(text, "src"); });
}

inline void expectMessage(const std::string& message, const std::vector<std::string>& needles) {
  EXPECT_FALSE(message.empty()) << "no error";
  EXPECT_LT(message.size(), kShortLine) << message.substr(0, 2000);
  EXPECT_EQ(message.find('\n'), std::string::npos) << message.substr(0, 2000);
  for (const auto& n : needles)
    EXPECT_NE(message.find(n), std::string::npos) << "'" << n << "' not in: " << message;
}

}  // namespace ts::test
