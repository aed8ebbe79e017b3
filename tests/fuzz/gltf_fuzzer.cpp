// libFuzzer target: the bytes of a .gltf or .glb file (the "glTF" magic decides) through
// tileshade's glTF loader: the JSON checks, tinygltf, accessor reading, images, lights, cameras.
// Any outcome but a Scene or a ts::Error (a crash, a sanitizer report, a hang, another exception)
// is a bug. External URIs resolve in an empty temporary folder.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "scene/scene_loader.h"
#include "util/error.h"

namespace {
std::string emptyFolder() {
  char name[] = "/tmp/tileshade_gltf_fuzz_XXXXXX";
  const char* made = mkdtemp(name);
  return made ? made : "/nonexistent";
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string baseDir = emptyFolder();
  std::vector<std::string> warnings;  // collected, not printed
  try {
    ts::Scene scene = ts::loadGltfFromMemory(data, size, baseDir, "fuzz.gltf", &warnings);
    (void)scene;
  } catch (const ts::Error&) {
    // a clear one-line error: the expected outcome for a bad file
  }
  return 0;
}
