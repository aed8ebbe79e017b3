#include "techniques/technique_knobs.h"

#include "shading/shading_cpu.h"

namespace ts {

// The enumerators are the kernels' constants: the build options pass them as numbers.
static_assert(int(CullTest::Rect) == TS_CULL_RECT && int(CullTest::Frustum) == TS_CULL_FRUSTUM &&
              int(CullTest::Aabb) == TS_CULL_AABB);
static_assert(int(SpotCulling::Cone) == TS_SPOT_CULL_CONE &&
              int(SpotCulling::BoundSphere) == TS_SPOT_CULL_BOUND_SPHERE &&
              int(SpotCulling::RangeSphere) == TS_SPOT_CULL_RANGE_SPHERE);
static_assert(int(RangeModel::Windowed) == TS_MODEL_WINDOWED &&
              int(RangeModel::Physical) == TS_MODEL_PHYSICAL);

const EnumNames<CullTest>& cullTestNames() {
  static const EnumNames<CullTest> names(
      "culling test", {{CullTest::Rect, "rect", "projected sphere + depth range"},
                       {CullTest::Frustum, "frustum", "+ tile side planes"},
                       {CullTest::Aabb, "aabb", "+ tile box"}});
  return names;
}

const EnumNames<SpotCulling>& spotCullingNames() {
  static const EnumNames<SpotCulling> names(
      "spot culling",
      {{SpotCulling::Cone, "cone", "their cone: rectangle, depth extent and per-tile cone test"},
       {SpotCulling::BoundSphere, "bound-sphere", "the cone's bounding sphere"},
       {SpotCulling::RangeSphere, "range-sphere", "as a point light"}});
  return names;
}

const EnumNames<MathMode>& mathModeNames() {
  static const EnumNames<MathMode> names("shading arithmetic",
                                         {{MathMode::Precise, "precise"},
                                          {MathMode::Fast, "fast", "-cl-fast-relaxed-math"},
                                          {MathMode::Native, "native", "native_ functions"}});
  return names;
}

const EnumNames<RangeModel>& rangeModelNames() {
  static const EnumNames<RangeModel> names(
      "range model", {{RangeModel::Windowed, "windowed", "smoothly to zero at the range"},
                      {RangeModel::Physical, "physical", "inverse square, no cut"}});
  return names;
}

const EnumNames<ShadowStorage>& shadowStorageNames() {
  static const EnumNames<ShadowStorage> names(
      "shadow storage",
      {{ShadowStorage::Atlas, "atlas", "every light's maps resident in one atlas"},
       {ShadowStorage::PerLight, "per-light",
        "deferred and deferred-stencil: one small atlas reused, each light's maps drawn just "
        "before its pass"}});
  return names;
}

const EnumNames<int>& laneNames() {
  static const EnumNames<int> names(
      "lanes width",
      {{0, "auto", "on CPU devices 16 for tiled, tiled-single, clustered and brute, else 1"},
       {1, "1", "one work-item per pixel"},
       {2, "2"},
       {4, "4"},
       {8, "8"},
       {16, "16", "vectors"}});
  return names;
}

}  // namespace ts
