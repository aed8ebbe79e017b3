#include "bench/bench_config.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdio>
#include <regex>
#include <set>
#include <sstream>

#include "raster/shadow_maps.h"
#include "util/checked_size.h"
#include "util/error.h"
#include "util/short_text.h"
#include "util/option_values.h"

namespace ts {
namespace {

// Shortest text that reads back as the same float ("12.5", not "12.500000").
std::string floatText(float v) {
  char buf[32];
  for (int p = 1; p <= 9; ++p) {
    std::snprintf(buf, sizeof buf, "%.*g", p, double(v));
    if (std::stof(buf) == v) break;
  }
  return buf;
}

std::string oneOf(const std::string& option, const std::string& value,
                  const std::vector<std::string>& known) {
  std::string s = trimmed(value);
  if (std::find(known.begin(), known.end(), s) != known.end()) return s;
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  badOptionValue(option, value, "expected one of " + list);
}

std::string joinedVariants() {
  std::string s;
  for (const auto& v : builtinVariants()) s += (s.empty() ? "" : ", ") + v;
  return s;
}

std::vector<BenchDimension> makeDimensions() {
  std::vector<BenchDimension> d;
  auto add = [&](std::string name, std::string help, bool affectsFrame,
                 std::function<void(BenchConfig&, const std::string&)> set,
                 std::function<std::string(const BenchConfig&)> get) {
    BenchDimension dim;
    dim.name = std::move(name);
    dim.help = std::move(help);
    dim.affectsFrame = affectsFrame;
    dim.set = std::move(set);
    dim.get = std::move(get);
    dim.defaultValue = dim.get(BenchConfig{});
    d.push_back(std::move(dim));
  };
  // Order = nesting order of the product (first = outermost) and of the CSV columns.
  add(
      "device", "OpenCL device(s): cpu, gpu, an index or a name substring (`tileshade devices`)",
      false,
      [](BenchConfig& c, const std::string& v) {
        std::string s = trimmed(v);
        c.device = s == "default" ? "" : s;
      },
      [](const BenchConfig& c) { return c.device.empty() ? std::string("default") : c.device; });
  add(
      "scene",
      "scene(s): builtin:street, builtin:atrium, a .gltf/.glb path, or gbuffer:DIR (an "
      "imported G-buffer: render --dump's folder or a descriptor .json)",
      true,
      [](BenchConfig& c, const std::string& v) {
        std::string s = trimmed(v);
        if (s.empty()) badOptionValue("--scene", v, "expected a scene");
        c.scene = s;
      },
      [](const BenchConfig& c) { return c.scene; });
  add(
      "raster",
      "rasterizer(s) of the G-buffer: " + rasterBackendNames().list() + " (OpenGL; docs/opengl.md)",
      true,
      [](BenchConfig& c, const std::string& v) {
        c.raster = rasterBackendNames().parseOption("--raster", v);
      },
      [](const BenchConfig& c) { return toString(c.raster); });
  // After bench.csv files existed: keyed off default, as the shadow dimensions.
  add(
      "msaa",
      "MSAA samples a pixel: 1, 2, 4, 8 (above 1: --raster gl, tiled-forward and "
      "tiled-forward-prez; the error against the per-sample reference)",
      true,
      [](BenchConfig& c, const std::string& v) {
        c.msaa = int(parseInteger("--msaa", v, 1, 8));
        checkMsaa(c.msaa, RasterBackend::Gl);  // the count; the rasterizer per configuration
      },
      [](const BenchConfig& c) { return std::to_string(c.msaa); });
  d.back().keyedOffDefault = true;
  add(
      "variant",
      "built-in scene variant(s), each a '+' list of " + joinedVariants() +
          " (none: the scene as designed)",
      true,
      [](BenchConfig& c, const std::string& v) {
        std::string s = trimmed(v);
        std::replace(s.begin(), s.end(), '+', ',');
        if (s == "none") s.clear();
        for (const auto& part : splitList(s, ',')) oneOf("--variant", part, builtinVariants());
        c.variant = s;
      },
      [](const BenchConfig& c) {
        std::string s = c.variant.empty() ? std::string("none") : c.variant;
        std::replace(s.begin(), s.end(), ',', '+');
        return s;
      });
  add(
      "blend",
      "glTF alphaMode BLEND materials: " + blendPolicyNames().list() +
          " (refuse: such a scene is refused; blend: composited by the forward techniques and "
          "tiled's hybrid)",
      true,
      [](BenchConfig& c, const std::string& v) {
        c.blend = blendPolicyNames().parseOption("--blend", v);
      },
      [](const BenchConfig& c) { return toString(c.blend); });
  add(
      "shading_model", "shading model(s): auto (the scene's own), " + shadingModelNames().list(),
      true,
      [](BenchConfig& c, const std::string& v) {
        std::vector<std::string> known{"auto"};
        for (const auto& name : shadingModelNames().names()) known.push_back(name);
        c.shadingModel = oneOf("--shading-model", v, known);
      },
      [](const BenchConfig& c) { return c.shadingModel; });
  add(
      "light_set",
      "light set(s) (street: many, few; atrium: small, big, mixed, thesis-small, thesis-big, "
      "thesis-big-shadows, thesis-mixed); default: the scene's",
      true,
      [](BenchConfig& c, const std::string& v) {
        std::string s = trimmed(v);
        c.lightSet = s == "default" ? "" : s;
      },
      [](const BenchConfig& c) {
        return c.lightSet.empty() ? std::string("default") : c.lightSet;
      });
  d.back().option = "--lights";  // as in `tileshade render`
  add(
      "light_count", "number(s) of lights (-1: the set's own)", true,
      [](BenchConfig& c, const std::string& v) {
        c.lightCount = int(parseInteger("--light-count", v, -1, kMaxLightCount));
      },
      [](const BenchConfig& c) { return std::to_string(c.lightCount); });
  add(
      "light_range", "light range(s) overriding every light's (0: keep), scene units", true,
      [](BenchConfig& c, const std::string& v) {
        c.lightRange = parseNumber("--light-range", v, NumberRule::AtLeastZero);
      },
      [](const BenchConfig& c) { return floatText(c.lightRange); });
  add(
      "light_threshold", "ranges from the attenuation threshold t (0: keep the scene's)", true,
      [](BenchConfig& c, const std::string& v) {
        c.lightThreshold = parseNumber("--light-threshold", v, NumberRule::AtLeastZero);
      },
      [](const BenchConfig& c) { return floatText(c.lightThreshold); });
  // The shadow dimensions (issue #18) came after bench.csv files existed: keyed off default.
  add(
      "shadows",
      "shadow-casting lights: default (the scene's own marks), none, all, or N (the N lights of "
      "largest range); their maps are drawn every frame (shadow_ms, shadow_bytes)",
      true,
      [](BenchConfig& c, const std::string& v) {
        const std::string s = trimmed(v);
        if (s == "default") c.shadows.clear();
        else if (s == "none" || s == "all") c.shadows = s;
        else c.shadows = std::to_string(parseInteger("--shadows", s, 0, kMaxLightCount));
      },
      [](const BenchConfig& c) { return c.shadows.empty() ? std::string("default") : c.shadows; });
  d.back().keyedOffDefault = true;
  add(
      "shadow_map_size",
      "texels a side of a point or spot light's shadow-map face (a power of two, 16..8192)", true,
      [](BenchConfig& c, const std::string& v) {
        c.shadowMapSize =
            int(parseInteger("--shadow-map-size", v, kShadowMinFaceSize, kShadowMaxFaceSize));
        checkShadowAtlasOptions({c.shadowMapSize, c.shadowBudgetMB});
      },
      [](const BenchConfig& c) { return std::to_string(c.shadowMapSize); });
  d.back().keyedOffDefault = true;
  add(
      "shadow_budget",
      "the shadow atlas's memory budget(s) in MB (MiB, > 0 and <= 4096): lights lose resolution "
      "beyond it, the least important first",
      true,
      [](BenchConfig& c, const std::string& v) {
        c.shadowBudgetMB = double(parseNumber("--shadow-budget", v, NumberRule::AboveZero));
        checkShadowAtlasOptions({c.shadowMapSize, c.shadowBudgetMB});
      },
      [](const BenchConfig& c) { return floatText(float(c.shadowBudgetMB)); });
  d.back().keyedOffDefault = true;
  add(
      "shadow_filter", "how shading samples a shadow map: none, pcf2, pcf3, pcf5", true,
      [](BenchConfig& c, const std::string& v) {
        c.shadowFilter = shadowFilterName(parseShadowFilter(trimmed(v)));
      },
      [](const BenchConfig& c) { return c.shadowFilter; });
  d.back().keyedOffDefault = true;
  add(
      "shadow_bias",
      "shadow depth bias(es) C:S (constant:slope, texels) or receiver:C (receiver plane; "
      "docs/shadows.md)",
      true,
      [](BenchConfig& c, const std::string& v) {
        // ':' inside a value, as ',' separates a list's values (render's --shadow-bias C,S).
        std::string s = trimmed(v);
        std::replace(s.begin(), s.end(), ':', ',');
        ShadowSampling sampling;
        try {
          parseShadowBias(s, sampling);
        } catch (const Error&) {  // render's message names its C,S form
          badOptionValue("--shadow-bias", v,
                         "expected C:S or receiver:C, finite numbers >= 0 (constant:slope; ':' "
                         "as ',' separates values)");
        }
        c.shadowBias = shadowBiasText(sampling);
      },
      [](const BenchConfig& c) {
        std::string s = c.shadowBias;
        std::replace(s.begin(), s.end(), ',', ':');
        return s;
      });
  d.back().keyedOffDefault = true;
  add(
      "seed", "seed(s) of the built-in scenes", true,
      [](BenchConfig& c, const std::string& v) {
        c.seed = uint32_t(parseInteger("--seed", v, 0, 0xffffffffLL));
      },
      [](const BenchConfig& c) { return std::to_string(c.seed); });
  add(
      "resolution", "image size(s) WxH, e.g. 1280x720,1920x1080", true,
      [](BenchConfig& c, const std::string& v) {
        auto [w, h] = parseResolution(v);
        c.width = w;
        c.height = h;
      },
      [](const BenchConfig& c) {
        return std::to_string(c.width) + "x" + std::to_string(c.height);
      });
  add(
      "gbuffer", "G-buffer precision(s): " + gbufferFormatNames().list(), false,
      [](BenchConfig& c, const std::string& v) {
        c.format = gbufferFormatNames().parseOption("--gbuffer", v);
      },
      [](const BenchConfig& c) { return toString(c.format); });
  add(
      "features",
      "what the kernels and the G-buffer model: auto (the scene's needs), general, or "
      "a '+' list of specular, emissive, textures, point, spot, directional, normal_maps, shadows",
      false,
      [](BenchConfig& c, const std::string& v) {
        std::string s = trimmed(v);
        std::replace(s.begin(), s.end(), '+', ',');
        if (s.empty()) badOptionValue("--features", v, "expected auto, general or a list");
        c.features = s;
      },
      [](const BenchConfig& c) {
        std::string s = c.features;
        std::replace(s.begin(), s.end(), ',', '+');
        return s;
      });
  add(
      "technique", "technique(s), or all", false,
      [](BenchConfig& c, const std::string& v) {
        c.technique = oneOf("--technique", v, techniqueNames());
      },
      [](const BenchConfig& c) { return c.technique; });
  add(
      "tile", "tile size(s) N or WxH, e.g. 8,16,32,64,32x16", false,
      [](BenchConfig& c, const std::string& v) {
        auto [w, h] = parseTileSize(v);
        c.tileWidth = w;
        c.tileHeight = h;
      },
      [](const BenchConfig& c) {
        return std::to_string(c.tileWidth) + "x" + std::to_string(c.tileHeight);
      });
  add(
      "spot_culling", "spot lights culled as: " + spotCullingNames().list(), false,
      [](BenchConfig& c, const std::string& v) {
        c.spotCulling = spotCullingNames().parseOption("--spot-culling", v);
      },
      [](const BenchConfig& c) { return toString(c.spotCulling); });
  add(
      "culling", "per-tile light test(s): " + cullTestNames().list(), false,
      [](BenchConfig& c, const std::string& v) {
        c.culling = cullTestNames().parseOption("--culling", v);
      },
      [](const BenchConfig& c) { return toString(c.culling); });
  add(
      "depth_split",
      "tiles: split each tile's depth range at its middle and cull against both "
      "halves: " +
          switchNames().list(),
      false,
      [](BenchConfig& c, const std::string& v) {
        c.depthSplit = switchNames().parseOption("--depth-split", v);
      },
      [](const BenchConfig& c) { return std::string(switchNames().name(c.depthSplit)); });
  d.back().keyedOffDefault = true;  // added after bench.csv files existed
  add(
      "math", "shading arithmetic: " + mathModeNames().list(), false,
      [](BenchConfig& c, const std::string& v) {
        c.math = mathModeNames().parseOption("--math", v);
      },
      [](const BenchConfig& c) { return toString(c.math); });
  add(
      "slices", "depth slices of clustered shading", false,
      [](BenchConfig& c, const std::string& v) {
        c.clusterSlices = int(parseInteger("--slices", v, 1, kMaxClusterSlices));
      },
      [](const BenchConfig& c) { return std::to_string(c.clusterSlices); });
  add(
      "lanes", "pixels shaded together per light: " + laneNames().help(), false,
      [](BenchConfig& c, const std::string& v) { c.lanes = laneNames().parseOption("--lanes", v); },
      [](const BenchConfig& c) { return lanesName(c.lanes); });
  add(
      "shadow_storage",
      "where the shadow maps live: " + shadowStorageNames().list() +
          " (per-light: deferred and deferred-stencil only; the sweep leaves out the other "
          "techniques' per-light configurations, with a line)",
      false,
      [](BenchConfig& c, const std::string& v) {
        c.shadowStorage = shadowStorageNames().parseOption("--shadow-storage", v);
      },
      [](const BenchConfig& c) { return toString(c.shadowStorage); });
  d.back().keyedOffDefault = true;  // added after bench.csv files existed
  return d;
}

uint64_t fnv1a(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

std::string BenchDimension::optionName() const {
  if (!option.empty()) return option;
  std::string o = "--" + name;
  std::replace(o.begin(), o.end(), '_', '-');
  return o;
}

const std::vector<BenchDimension>& benchDimensions() {
  static const std::vector<BenchDimension> dims = makeDimensions();
  return dims;
}

bool BenchDimension::matchesKey(const std::string& key) const {
  std::string stem = optionName().substr(2), underscored = stem;
  std::replace(underscored.begin(), underscored.end(), '-', '_');
  return key == name || key == stem || key == underscored;
}

const BenchDimension& findDimension(const std::string& name) {
  for (const auto& d : benchDimensions())
    if (d.name == name) return d;
  for (const auto& d : benchDimensions())
    if (d.matchesKey(name)) return d;
  std::string known;
  for (const auto& d : benchDimensions()) known += (known.empty() ? "" : ", ") + d.name;
  throw Error("unknown sweep dimension '" + shortText(name) + "' (known: " + known + ")");
}

void BenchSweep::set(const std::string& dimension, std::vector<std::string> list) {
  values[findDimension(dimension).name] = std::move(list);
}

std::string BenchConfig::key() const {
  std::string k;
  for (const auto& d : benchDimensions()) {
    const std::string value = d.get(*this);
    if (d.keyedOffDefault && value == d.defaultValue) continue;
    k += (k.empty() ? "" : ";") + d.name + "=" + value;
  }
  return k;
}

std::string BenchConfig::frameKey() const {
  std::string k;
  for (const auto& d : benchDimensions())
    if (d.affectsFrame) k += (k.empty() ? "" : ";") + d.name + "=" + d.get(*this);
  return k;
}

std::string BenchConfig::id() const {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%012llx", (unsigned long long)(fnv1a(key()) >> 16));
  return buf;
}

std::vector<BenchConfig> expandSweep(const BenchSweep& sweep, std::vector<std::string>* notes) {
  for (const auto& [name, list] : sweep.values) findDimension(name);
  // Each dimension's values, each once (" 16" and "16x16" are one tile size), validated; then the
  // size of the product, before any of it is built.
  std::vector<std::pair<const BenchDimension*, std::vector<std::string>>> lists;
  CheckedSize total(1);
  for (const auto& dim : benchDimensions()) {
    auto it = sweep.values.find(dim.name);
    if (it == sweep.values.end()) continue;
    std::vector<std::string> values;
    std::set<std::string> canonical;
    auto add = [&](const std::string& v) {
      BenchConfig probe;
      dim.set(probe, v);
      if (canonical.insert(dim.get(probe)).second) values.push_back(v);
    };
    for (const auto& v : it->second)
      for (const auto& item : splitList(v)) {
        if (dim.name == "technique" && item == "all") {
          // The G-buffer techniques: the forward ones need --raster gl frames, so by name only.
          for (const auto& t : gbufferTechniqueNames()) add(t);
        } else {
          add(item);
        }
      }
    if (values.empty()) throw Error(dim.optionName() + ": empty list");
    total = total * values.size();
    if (!total.fitsWithin(kMaxBenchConfigurations))
      throw Error("the sweep has more than " + std::to_string(kMaxBenchConfigurations) +
                  " configurations (the product of the lists, up to " + dim.optionName() +
                  "): split it into several runs");
    lists.emplace_back(&dim, std::move(values));
  }
  std::vector<BenchConfig> configs{BenchConfig{}};
  configs.reserve(total.value());
  for (const auto& [dim, values] : lists) {
    std::vector<BenchConfig> next;
    next.reserve(configs.size() * values.size());
    for (const auto& c : configs)
      for (const auto& v : values) {
        BenchConfig x = c;
        dim->set(x, v);
        next.push_back(x);
      }
    configs = std::move(next);
  }
  std::vector<BenchConfig> unique;
  std::set<std::string> seen;
  // Per-light shadow storage is for the techniques that shade one light per pass: a sweep of
  // techniques x storages leaves the others' per-light points out, and says how many.
  std::map<std::string, size_t> leftOut;
  for (auto& c : configs) {
    if (c.shadowStorage == ShadowStorage::PerLight &&
        !findTechnique(c.technique).reusesShadowMaps) {
      ++leftOut[c.technique];
      continue;
    }
    if (seen.insert(c.key()).second) unique.push_back(std::move(c));
  }
  if (unique.empty() && !leftOut.empty()) throw Error(shadowStorageRefusal(leftOut.begin()->first));
  if (notes)
    for (const auto& [technique, count] : leftOut)
      notes->push_back("left out " + std::to_string(count) + " configuration(s) of " + technique +
                       " with shadow_storage per-light (it shades every light at once and needs "
                       "every map resident)");
  return unique;
}

void FrameSpec::validate() const { resolve(240); }

std::vector<int> FrameSpec::resolve(int pathLength) const {
  std::string s = trimmed(text);
  std::smatch m;
  std::vector<int> frames;
  const int kMaxFrame = 1 << 20;
  static const std::regex rangeForm(R"((\d{1,7}):(\d{1,7})(?::(\d{1,7}))?)"),
      countForm(R"(\d{1,7})"), listForm(R"(\d{1,7}(\s*;\s*\d{1,7})+)");
  auto badFrames = [&](const std::string& what) {
    badOptionValue("--frames", text, what + " (forms: A:B[:S], N, all, a;b;c)");
  };
  if (s == "all") {
    for (int k = 0; k < std::max(pathLength, 1); ++k) frames.push_back(k);
  } else if (std::regex_match(s, m, rangeForm)) {
    int a = std::stoi(m[1]), b = std::stoi(m[2]), step = m[3].matched ? std::stoi(m[3]) : 1;
    if (step < 1) badFrames("the step must be at least 1");
    if (b <= a) badFrames("the range A:B must have B > A");
    if (b > kMaxFrame) badFrames("frames must be below 2^20");
    for (int k = a; k < b; k += step) frames.push_back(k);
  } else if (std::regex_match(s, countForm)) {
    int n = std::stoi(s);
    if (n < 1) badFrames("the frame count must be at least 1");
    if (n > 100000) badFrames("at most 100000 frames");
    if (pathLength < n) {
      for (int k = 0; k < n; ++k) frames.push_back(k);
    } else {
      for (int k = 0; k < n; ++k) frames.push_back(int((long long)k * pathLength / n));
    }
  } else if (std::regex_match(s, listForm)) {
    for (const auto& item : splitList(s, ';')) frames.push_back(std::stoi(item));
  } else {
    badFrames("unrecognised frame list");
  }
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  return frames;
}

Shard Shard::parse(const std::string& value) {
  // The limit is stated in every refusal (once a 7-digit n was refused as "not k/n").
  const long long kMaxCount = 1000000;
  const std::string expected =
      "expected k/n with 0 <= k < n <= " + std::to_string(kMaxCount) + " (e.g. 0/3)";
  std::smatch m;
  std::string s = trimmed(value);
  if (!std::regex_match(s, m, std::regex(R"((\d+)/(\d+))")))
    badOptionValue("--shard", value, expected);
  auto number = [](const std::string& digits) {
    return digits.size() > 9 ? LLONG_MAX : std::stoll(digits);
  };
  long long index = number(m[1]), count = number(m[2]);
  if (count < 1 || count > kMaxCount || index >= count) badOptionValue("--shard", value, expected);
  Shard sh;
  sh.index = int(index);
  sh.count = int(count);
  return sh;
}

}  // namespace ts
