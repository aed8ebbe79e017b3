// libFuzzer target: a `--gbuffer-in` descriptor (gbuffer.json) through the strict JSON parser and
// the descriptor's checks, as `render --gbuffer-in` reads it before it opens the image; the same
// bytes as the shadow atlas descriptor it may name (shadow_atlas.json). Any outcome but success
// or a ts::Error is a bug.
#include <cstdint>
#include <string>

#include "gbuffer/gbuffer_files.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    ts::parseGBufferDescriptor(text, "fuzz/gbuffer.json");
  } catch (const ts::Error&) {
    // a clear one-line error: the expected outcome for a bad descriptor
  }
  try {
    ts::parseShadowAtlasFile(text, "fuzz/shadow_atlas.json");
  } catch (const ts::Error&) {
  }
  return 0;
}
