// The one list of techniques. Adding a technique = its own .cpp/.cl pair plus one line here.
#include <sstream>

#include "techniques/technique.h"
#include "techniques/techniques.h"
#include "util/error.h"

namespace ts {

const std::vector<TechniqueInfo>& techniqueRegistry() {
  static const std::vector<TechniqueInfo> registry = {
      {"tiled", "multi-kernel tiled deferred: depth min/max, light binning, per-pixel shading",
       makeTiledTechnique},
  };
  return registry;
}

std::vector<std::string> techniqueNames() {
  std::vector<std::string> names;
  for (const auto& t : techniqueRegistry()) names.push_back(t.name);
  return names;
}

const TechniqueInfo& findTechnique(const std::string& name) {
  for (const auto& t : techniqueRegistry())
    if (t.name == name) return t;
  std::ostringstream known;
  for (const auto& n : techniqueNames()) known << (known.tellp() ? ", " : "") << n;
  throw Error("unknown technique '" + name + "' (known: " + known.str() + ", all)");
}

std::unique_ptr<Technique> createTechnique(const std::string& name, ClContext& cl,
                                           const TechniqueConfig& config) {
  return findTechnique(name).create(cl, config);
}

std::string TechniqueConfig::kernelOptions() const {
  std::ostringstream o;
  o << (format == GBufferFormat::FP16 ? "-DTS_GBUFFER_FP16 " : "") << "-DTS_MODEL=" << shadingModel;
  if (!buildOptions.empty()) o << " " << buildOptions;
  return o.str();
}

}  // namespace ts
