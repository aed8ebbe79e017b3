#pragma once
// One exception type for user-facing failures: its message is printed as a single line
// ("tileshade: error: <message>") and the program exits non-zero.
#include <stdexcept>
#include <string>

namespace ts {

struct Error : std::runtime_error {
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace ts
