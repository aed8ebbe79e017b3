// TechniqueConfig on the host: its cache key (TechniqueConfig::key) tells every configuration
// apart.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "techniques/technique.h"

namespace ts {
namespace {

// check's technique cache is keyed on TechniqueConfig::key: a configuration that builds or launches
// differently must not share a key (one with other cluster slices reused a kernel built for 16).
TEST(TechniqueConfig, EveryFieldChangesTheKey) {
  const TechniqueConfig base;
  const std::vector<std::pair<std::string, std::function<void(TechniqueConfig&)>>> changes = {
      {"format", [](TechniqueConfig& c) { c.format = GBufferFormat::PACKED; }},
      {"features", [](TechniqueConfig& c) { c.features.directional = false; }},
      {"tileWidth", [](TechniqueConfig& c) { c.tileWidth = 8; }},
      {"tileHeight", [](TechniqueConfig& c) { c.tileHeight = 8; }},
      {"clusterSlices", [](TechniqueConfig& c) { c.clusterSlices = 32; }},
      {"presizeLists", [](TechniqueConfig& c) { c.presizeLists = false; }},
      {"localListCapacity", [](TechniqueConfig& c) { c.localListCapacity = 64; }},
      {"rangeModel", [](TechniqueConfig& c) { c.rangeModel = RangeModel::Physical; }},
      {"culling", [](TechniqueConfig& c) { c.culling = CullTest::Aabb; }},
      {"depthSplit", [](TechniqueConfig& c) { c.depthSplit = true; }},
      {"spotCulling", [](TechniqueConfig& c) { c.spotCulling = SpotCulling::BoundSphere; }},
      {"math", [](TechniqueConfig& c) { c.math = MathMode::Fast; }},
      {"buildOptions", [](TechniqueConfig& c) { c.buildOptions = "-cl-opt-disable"; }},
      {"lanes", [](TechniqueConfig& c) { c.lanes = 4; }},
  };
  for (const auto& [field, change] : changes) {
    TechniqueConfig c = base;
    change(c);
    EXPECT_NE(c.key(), base.key()) << field;
  }
}

}  // namespace
}  // namespace ts
