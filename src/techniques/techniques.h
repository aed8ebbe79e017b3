#pragma once
// Factories of the built-in techniques (one per src/techniques/<name>.cpp), listed in registry.cpp.
#include <memory>

#include "techniques/technique.h"

namespace ts {

std::unique_ptr<Technique> makeTiledTechnique(ClContext& cl, const TechniqueConfig& config);

}  // namespace ts
