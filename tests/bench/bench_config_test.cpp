// `tileshade bench`'s sweep (src/bench/bench_config.h): expansion in dimension order, value
// parsing, frame specs and shards, with one clear line for each bad value.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "bench/bench_config.h"
#include "bench/bench_run.h"
#include "bench_test_support.h"
#include "util/error.h"

namespace {

using ts::BenchSweep;
using ts::test::expectOneLineError;

TEST(BenchSweep, CartesianProductInDimensionOrder) {
  BenchSweep s;
  s.set("tile", {"8,32x16"});
  s.set("gbuffer", {"fp32", "fp16"});
  s.set("resolution", {"64x36"});
  s.set("light_count", {"1,10,100"});
  auto configs = ts::expandSweep(s);
  ASSERT_EQ(configs.size(), 2u * 2u * 3u);
  // light_count is outermost of these, then gbuffer, then tile (benchDimensions() order).
  EXPECT_EQ(configs[0].lightCount, 1);
  EXPECT_EQ(configs[0].format, ts::GBufferFormat::FP32);
  EXPECT_EQ(configs[0].tileWidth, 8);
  EXPECT_EQ(configs[0].tileHeight, 8);
  EXPECT_EQ(configs[1].tileWidth, 32);
  EXPECT_EQ(configs[1].tileHeight, 16);
  EXPECT_EQ(configs[2].format, ts::GBufferFormat::FP16);
  EXPECT_EQ(configs[4].lightCount, 10);
  std::set<std::string> keys, ids;
  for (const auto& c : configs) {
    EXPECT_EQ(c.width, 64);
    EXPECT_EQ(c.height, 36);
    keys.insert(c.key());
    ids.insert(c.id());
  }
  EXPECT_EQ(keys.size(), configs.size());
  EXPECT_EQ(ids.size(), configs.size());
}

TEST(BenchSweep, DefaultsDuplicatesAndAll) {
  auto one = ts::expandSweep(BenchSweep{});
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].technique, "tiled");
  EXPECT_EQ(one[0].width, 1280);
  BenchSweep s;
  s.set("tile", {"16", "16x16", " 16 "});
  EXPECT_EQ(ts::expandSweep(s).size(), 1u);  // the same configuration
  BenchSweep all;
  all.set("technique", {"all"});
  EXPECT_EQ(ts::expandSweep(all).size(), ts::gbufferTechniqueNames().size());
  // The key is stable and names every dimension (but those added later, at their default).
  std::string key = one[0].key();
  for (const auto& d : ts::benchDimensions())
    EXPECT_EQ(key.find(d.name + "=") != std::string::npos, !d.keyedOffDefault) << d.name;
  EXPECT_EQ(one[0].id(), ts::expandSweep(BenchSweep{})[0].id());
}

TEST(BenchSweep, TileSizesIncludingNonSquare) {
  EXPECT_EQ(ts::parseTileSize("16"), std::make_pair(16, 16));
  EXPECT_EQ(ts::parseTileSize("32x16"), std::make_pair(32, 16));
  EXPECT_EQ(ts::parseTileSize("8X64"), std::make_pair(8, 64));
  EXPECT_EQ(ts::parseTileSize(" 64 "), std::make_pair(64, 64));
  for (const char* bad : {"0", "abc", "16x", "x16", "300", "16x0", "-8", "16x16x2", ""})
    expectOneLineError([&] { ts::parseTileSize(bad); }, {"--tile"});
  EXPECT_EQ(ts::parseResolution("1920x1080"), std::make_pair(1920, 1080));
  expectOneLineError([] { ts::parseResolution("1920"); }, {"--resolution", "'1920'"});
}

TEST(BenchSweep, InvalidValuesGiveOneClearLine) {
  auto expand = [](const std::string& dim, const std::string& value) {
    BenchSweep s;
    s.set(dim, {value});
    ts::expandSweep(s);
  };
  expectOneLineError([&] { expand("gbuffer", "fp8"); }, {"--gbuffer", "fp8", "fp16"});
  expectOneLineError([&] { expand("technique", "nope"); }, {"--technique", "nope", "tiled"});
  expectOneLineError([&] { expand("tile", "16,abc"); }, {"--tile", "abc"});
  expectOneLineError([&] { expand("light_count", "many"); }, {"--light-count", "many"});
  expectOneLineError([&] { expand("light_range", "-3"); }, {"--light-range", "-3"});
  expectOneLineError([&] { expand("culling", "sphere"); }, {"--culling", "sphere"});
  expectOneLineError([&] { expand("tile", ","); }, {"--tile", "empty"});
  expectOneLineError(
      [] {
        BenchSweep s;
        s.set("colour", {"red"});
      },
      {"colour", "technique"});
}

TEST(BenchSweep, ShadowDimensionsRefuseBadValuesInOneLine) {
  for (const auto& [dim, value, needle] :
       std::vector<std::tuple<std::string, std::string, std::string>>{
           {"shadows", "some", "--shadows"},
           {"shadow_map_size", "100", "--shadow-map-size"},
           {"shadow_map_size", "8", "--shadow-map-size"},
           {"shadow_filter", "pcf4", "--shadow-filter"},
           {"shadow_bias", "1", "--shadow-bias"},
           {"shadow_bias", "-1:2", "--shadow-bias"},
           {"shadow_bias", "receiver", "--shadow-bias"},
           {"shadow_bias", "receiver:1:2", "--shadow-bias"},
           {"shadow_budget", "0", "--shadow-budget"},
           {"shadow_budget", "5000", "--shadow-budget"},
           {"shadow_budget", "lots", "--shadow-budget"},
           {"shadow_storage", "per-tile", "--shadow-storage"}}) {
    BenchSweep s;
    s.set(dim, {value});
    expectOneLineError([&] { ts::expandSweep(s); }, {needle});
  }
}

// The shadow dimensions' canonical values (added after bench.csv files existed: a
// configuration at their defaults keeps its id).
TEST(BenchSweep, ShadowDimensionsCanonicalAndKeyedOffDefault) {
  BenchSweep s;
  s.set("shadows", {"default,none,all,3"});
  s.set("shadow_bias", {"1.5:1.5,0.50:2"});
  auto configs = ts::expandSweep(s);
  ASSERT_EQ(configs.size(), 8u);
  EXPECT_EQ(configs[0].shadows, "");
  EXPECT_EQ(configs[2].shadows, "none");
  EXPECT_EQ(configs[6].shadows, "3");
  EXPECT_EQ(configs[1].shadowBias, "0.5,2");
  EXPECT_EQ(configs[0].key(), ts::BenchConfig{}.key());
  EXPECT_EQ(configs[0].key().find("shadow"), std::string::npos) << configs[0].key();
  EXPECT_NE(configs[1].key().find("shadow_bias=0.5:2"), std::string::npos) << configs[1].key();
}

// The receiver-plane bias as a bias value: canonical "receiver,C", keyed "receiver:C".
TEST(BenchSweep, ShadowBiasTakesTheReceiverPlane) {
  BenchSweep s;
  s.set("shadow_bias", {"receiver:0.50,1.5:1.5"});
  auto configs = ts::expandSweep(s);
  ASSERT_EQ(configs.size(), 2u);
  EXPECT_EQ(configs[0].shadowBias, "receiver,0.5");
  EXPECT_NE(configs[0].key().find("shadow_bias=receiver:0.5"), std::string::npos)
      << configs[0].key();
}

// shadow_budget (frame) and shadow_storage (technique) dimensions: canonical values, keyed off
// their defaults; a technique that needs every map resident has its per-light points left out,
// with a note, and a sweep of nothing else is refused in one line.
TEST(BenchSweep, ShadowBudgetAndStorageDimensions) {
  BenchSweep s;
  s.set("technique", {"tiled,deferred,deferred-stencil"});
  s.set("shadow_budget", {"64,0.50"});
  s.set("shadow_storage", {"atlas,per-light"});
  std::vector<std::string> notes;
  const auto configs = ts::expandSweep(s, &notes);
  ASSERT_EQ(configs.size(), 10u);  // 3 x 2 x 2, less tiled's two per-light points
  for (const auto& c : configs)
    EXPECT_FALSE(c.technique == "tiled" && c.shadowStorage == ts::ShadowStorage::PerLight);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("left out 2 configuration(s) of tiled with shadow_storage per-light"),
            std::string::npos)
      << notes[0];
  EXPECT_EQ(configs[0].key().find("shadow"), std::string::npos) << configs[0].key();
  size_t budgets = 0, storages = 0;
  for (const auto& c : configs) {
    budgets += c.key().find("shadow_budget=0.5") != std::string::npos;
    storages += c.key().find("shadow_storage=per-light") != std::string::npos;
    EXPECT_EQ(c.frameKey().find("shadow_storage"), std::string::npos) << c.frameKey();
  }
  EXPECT_EQ(budgets, 5u);
  EXPECT_EQ(storages, 4u);
  const ts::BenchDimension& budget = ts::findDimension("shadow_budget");
  ts::BenchConfig c;
  budget.set(c, "0.50");
  EXPECT_EQ(c.shadowBudgetMB, 0.5);
  EXPECT_EQ(budget.get(c), "0.5");
  EXPECT_TRUE(budget.affectsFrame);
  EXPECT_FALSE(ts::findDimension("shadow_storage").affectsFrame);
  // Nothing but tiled per-light: refused.
  BenchSweep only;
  only.set("technique", {"tiled"});
  only.set("shadow_storage", {"per-light"});
  expectOneLineError([&] { ts::expandSweep(only); }, {"--shadow-storage per-light", "tiled"});
}

TEST(BenchSweep, OptionsAndColumnsAreUnique) {
  std::set<std::string> options;
  for (const auto& d : ts::benchDimensions()) {
    EXPECT_TRUE(options.insert(d.optionName()).second) << d.optionName();
    EXPECT_TRUE(d.matchesKey(d.name));
  }
  EXPECT_EQ(ts::findDimension("lights").name, "light_set");  // the option stem works as a key
  for (const auto& cols : {ts::benchCsvColumns(), ts::summaryCsvColumns()}) {
    std::set<std::string> unique(cols.begin(), cols.end());
    EXPECT_EQ(unique.size(), cols.size());
  }
}

TEST(BenchSweep, FrameSpecs) {
  EXPECT_EQ(ts::FrameSpec{"0:120:10"}.resolve(240),
            (std::vector<int>{0, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110}));
  EXPECT_EQ(ts::FrameSpec{"5:8"}.resolve(240), (std::vector<int>{5, 6, 7}));
  EXPECT_EQ(ts::FrameSpec{"4"}.resolve(240), (std::vector<int>{0, 60, 120, 180}));
  EXPECT_EQ(ts::FrameSpec{"3"}.resolve(1), (std::vector<int>{0, 1, 2}));  // a one-camera path
  EXPECT_EQ(ts::FrameSpec{"all"}.resolve(5), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(ts::FrameSpec{"7;1;3;3"}.resolve(240), (std::vector<int>{1, 3, 7}));
  for (const char* bad : {"5:2", "x", "0:10:0", "0", "1,2", ""})
    expectOneLineError([&] { ts::FrameSpec{bad}.validate(); }, {"--frames"});
  std::vector<int> timed{0, 20, 40, 60, 80, 100};
  EXPECT_EQ(ts::selectErrorFrames("all", timed), timed);
  EXPECT_EQ(ts::selectErrorFrames("2", timed), (std::vector<int>{0, 60}));
  EXPECT_EQ(ts::selectErrorFrames("40:200", timed), (std::vector<int>{40, 60, 80, 100}));
  EXPECT_EQ(ts::selectErrorFrames("20;21", timed), (std::vector<int>{20}));
  expectOneLineError([&] { ts::selectErrorFrames("soon", timed); }, {"--error-frames"});
}

TEST(BenchSweep, ShardsPartitionTheConfigurationsExactly) {
  BenchSweep s;
  s.set("tile", {"8,16,32,64,32x16"});
  s.set("gbuffer", {"fp32,fp16"});
  s.set("light_count", {"1,2,3"});
  auto configs = ts::expandSweep(s);
  ASSERT_EQ(configs.size(), 30u);
  for (int n : {1, 2, 3, 4, 7, 31}) {
    std::vector<int> owners(configs.size(), 0);
    std::vector<size_t> perShard(size_t(n), 0);
    for (int k = 0; k < n; ++k) {
      ts::Shard sh = ts::Shard::parse(std::to_string(k) + "/" + std::to_string(n));
      for (size_t i = 0; i < configs.size(); ++i)
        if (sh.selects(i)) {
          ++owners[i];
          ++perShard[size_t(k)];
          EXPECT_EQ(int(i % size_t(n)), k);
        }
    }
    for (int o : owners) EXPECT_EQ(o, 1) << "n=" << n;
    for (size_t c : perShard) EXPECT_LE(c, (configs.size() + size_t(n) - 1) / size_t(n));
  }
  for (const char* bad : {"3/3", "1", "a/b", "-1/2", "0/0"})
    expectOneLineError([&] { ts::Shard::parse(bad); }, {"--shard"});
}

TEST(BenchShard, LimitIsTheOneStated) {
  EXPECT_EQ(ts::Shard::parse("999999/1000000").count, 1000000);
  expectOneLineError([] { ts::Shard::parse("0/1000001"); }, {"n <= 1000000", "'0/1000001'"});
  expectOneLineError([] { ts::Shard::parse("0/99999999999999999999"); }, {"n <= 1000000"});
  expectOneLineError([] { ts::Shard::parse("3/3"); }, {"0 <= k < n"});
}

}  // namespace
