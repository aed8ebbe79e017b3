#include "techniques/math_mode_note.h"

namespace ts {
namespace {

bool isPoclCpu(const std::string& device, const std::string& type) {
  return type == "cpu" && device.find("Portable Computing Language") != std::string::npos;
}

}  // namespace

std::string mathModeNote(MathMode math, const std::string& device, const std::string& type) {
  // PoCL's native_sqrt, native_rsqrt and native_exp2 are its precise functions: the kernels
  // compile to the same machine code (identical disassembly, issue #19).
  if (math == MathMode::Native && isPoclCpu(device, type))
    return "--math native: the same machine code as precise on this device (PoCL's native_ "
           "functions are its precise ones): no faster, the same image";
  // -cl-fast-relaxed-math changes the code, but it measured no faster than precise on PoCL in any
  // of tiled, tiled-single, clustered and brute (bench/RESULTS.md, issue #19), with 2.4x the error.
  if (math == MathMode::Fast && isPoclCpu(device, type))
    return "--math fast: not measurably faster than precise on this device (PoCL; "
           "bench/RESULTS.md, "
           "issue #19), with more error (docs/accuracy.md)";
  return "";
}

}  // namespace ts
