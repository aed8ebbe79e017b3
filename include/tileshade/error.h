#pragma once
// The one exception type of tileshade's API and command: its message is one line (the command
// prints it as "tileshade: error: <message>" and exits non-zero).
#include <stdexcept>
#include <string>

namespace ts {

struct Error : std::runtime_error {
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace ts
