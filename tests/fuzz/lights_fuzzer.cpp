// libFuzzer target: a G-buffer import's lights.json through the strict JSON parser and the light
// checks, as `render --gbuffer-in` reads it. Any outcome but success or a ts::Error is a bug.
#include <cstdint>
#include <string>

#include "gbuffer/gbuffer_files.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    ts::parseLightsFile(std::string(reinterpret_cast<const char*>(data), size), "fuzz/lights.json");
  } catch (const ts::Error&) {
    // a clear one-line error: the expected outcome for a bad lights file
  }
  return 0;
}
