#pragma once
// What a `--math` setting buys on a device, where it is known to buy nothing: `render` and `bench`
// print the note, so a user who asks for faster arithmetic learns that this device gives none
// (docs/accuracy.md, "Shading arithmetic"; bench/RESULTS.md, issue #19). The setting still runs:
// a script that passes it on every device keeps working.
#include <string>

#include "techniques/technique_knobs.h"

namespace ts {

// device: "platform / device" (Device::name()); type: "cpu", "gpu", ... Empty when the setting
// is expected to change the code on that device (or is `precise`).
std::string mathModeNote(MathMode math, const std::string& device, const std::string& type);

}  // namespace ts
