#pragma once
// The knobs of TechniqueConfig that choose among named variants of the kernels, each an enum whose
// values are the kernels' constants (the -D build options carry the numbers) and one name table
// (util/enum_names.h) that every command, file and --help goes through. A new value = one
// enumerator + one row of its table (technique_knobs.cpp) + the kernels' code for it.
#include <string>

#include "util/enum_names.h"

namespace ts {

// Per-tile light test (TS_CULL, kernels/culling.h; every one conservative).
enum class CullTest { Rect = 0, Frustum = 1, Aabb = 2 };
// How spot lights are culled (TS_SPOT_CULL, kernels/culling.h).
enum class SpotCulling { Cone = 0, BoundSphere = 1, RangeSphere = 2 };
// Shading arithmetic: the OpenCL compiler's precise functions, -cl-fast-relaxed-math, or the
// native_ functions (TS_NATIVE_MATH, kernels/shading.h).
enum class MathMode { Precise, Fast, Native };
// How a light's contribution ends at its range (TS_MODEL, kernels/shading.h): windowed (smoothly
// to zero at the range, what the kernels shade) or physical (inverse square, no cut; the
// reference's "truth" for the bias of the cut).
enum class RangeModel { Windowed = 0, Physical = 1 };
// Where the shadow maps live while a frame is shaded (issue #18; docs/shadows.md): one atlas
// holding every light's maps, or (traditional deferred only, which shades one light per launch)
// one small atlas reused by every light, its maps drawn just before its launch.
enum class ShadowStorage { Atlas, PerLight };

const EnumNames<CullTest>& cullTestNames();
const EnumNames<SpotCulling>& spotCullingNames();
const EnumNames<MathMode>& mathModeNames();
const EnumNames<RangeModel>& rangeModelNames();
const EnumNames<ShadowStorage>& shadowStorageNames();

inline std::string toString(CullTest v) { return cullTestNames().name(v); }
inline std::string toString(SpotCulling v) { return spotCullingNames().name(v); }
inline std::string toString(MathMode v) { return mathModeNames().name(v); }
inline std::string toString(RangeModel v) { return rangeModelNames().name(v); }
inline std::string toString(ShadowStorage v) { return shadowStorageNames().name(v); }

// TechniqueConfig::lanes, pixels shaded together per light (kernels/lanes.h): 0 = auto, or a
// width the kernels are built for (TS_LANES; floatN exists for these N).
const EnumNames<int>& laneNames();
// "auto" -> 0, or the width; throws ts::Error naming the known values otherwise.
inline int parseLanes(const std::string& text) { return laneNames().parse(text); }
// "auto" for 0, else the number.
inline std::string lanesName(int lanes) { return laneNames().name(lanes); }

}  // namespace ts
