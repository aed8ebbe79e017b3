#pragma once
// Helpers of the bench suites (bench_test.cpp, bench_config_test.cpp, bench_stats_test.cpp).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "util/error.h"

namespace ts::test {

// A fresh folder per test (tests run in parallel processes).
inline std::string tempDir(const std::string& name) {
  std::filesystem::path p = std::filesystem::temp_directory_path() /
                            ("tileshade_bench_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

// Expects a ts::Error whose message is one line containing every needle.
template <typename F>
void expectOneLineError(F&& f, std::vector<std::string> needles) {
  try {
    f();
    ADD_FAILURE() << "no ts::Error thrown";
  } catch (const ts::Error& e) {
    std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    for (const auto& n : needles) EXPECT_NE(m.find(n), std::string::npos) << m << " lacks " << n;
  }
}

}  // namespace ts::test
