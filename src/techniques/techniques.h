#pragma once
// Factories of the built-in techniques (one per src/techniques/<name>.cpp), listed in registry.cpp.
#include <memory>

#include "techniques/technique.h"

namespace ts {

std::unique_ptr<Technique> makeTiledTechnique(ClContext& cl, const TechniqueConfig& config);
std::unique_ptr<Technique> makeClusteredTechnique(ClContext& cl, const TechniqueConfig& config);
std::unique_ptr<Technique> makeTiledSingleTechnique(ClContext& cl, const TechniqueConfig& config);
std::unique_ptr<Technique> makeBruteTechnique(ClContext& cl, const TechniqueConfig& config);
std::unique_ptr<Technique> makeDeferredTechnique(ClContext&, const TechniqueConfig&, bool stencil);
// prez: tiled-forward-prez (depth pre-pass, tile depth bounds, depth EQUAL); else tiled-forward.
std::unique_ptr<Technique> makeTiledForwardTechnique(ClContext&, const TechniqueConfig&, bool prez);
std::unique_ptr<Technique> makeClusteredForwardTechnique(ClContext&, const TechniqueConfig&);
std::unique_ptr<Technique> makeForwardTechnique(ClContext&, const TechniqueConfig&);
std::unique_ptr<Technique> makeForwardSingleTechnique(ClContext&, const TechniqueConfig&);

}  // namespace ts
