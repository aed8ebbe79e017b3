#pragma once
// One exception type for user-facing failures: its message is printed as a single line
// ("tileshade: error: <message>") and the program exits non-zero.
#include <new>
#include <stdexcept>
#include <string>

#include "tileshade/error.h"  // ts::Error, part of the public API

namespace ts {

// Runs f(); a std::bad_alloc inside becomes ts::Error("out of memory " + what), so the message
// says what was too big (e.g. "out of memory rasterizing a 16384x16384 frame") instead of
// "std::bad_alloc".
template <typename F>
auto outOfMemoryAs(const std::string& what, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    throw Error("out of memory " + what);
  }
}

}  // namespace ts
