// Images with NaN/inf pixels (issue #12): counted, their errors infinite in the stats and the
// heat map, never reported as exact (src/reference/error_metrics.h).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

#include "reference/error_metrics.h"
#include "render/stats.h"

using json = nlohmann::json;

namespace {

TEST(HostileStats, NonFinitePixelsAreCountedAndNeverExact) {
  ts::ReferenceImage ref;
  ref.width = 2;
  ref.height = 1;
  ref.rgb = {glm::dvec3(0.5), glm::dvec3(1.0)};
  ref.peak = 1.0;
  std::vector<glm::vec4> exact = {glm::vec4(0.5f), glm::vec4(1.0f)};
  ts::ErrorStats e = ts::compareToReference(exact, ref, 1e-4);
  EXPECT_TRUE(std::isinf(e.psnr) && e.psnr > 0);  // exact
  EXPECT_EQ(e.nonfinitePixels, 0u);

  std::vector<glm::vec4> broken = {glm::vec4(std::nanf("")), glm::vec4(1.0f)};
  e = ts::compareToReference(broken, ref, 1e-4);
  EXPECT_EQ(e.nonfinitePixels, 1u);
  EXPECT_EQ(e.pixelsAboveTolerance, 1u);
  EXPECT_TRUE(std::isinf(e.maxAbs) && e.maxAbs > 0);
  EXPECT_TRUE(std::isinf(e.psnr) && e.psnr < 0);
  json j = ts::errorJson(e);
  EXPECT_EQ(j["psnr_db"], "-inf");
  EXPECT_EQ(j["max_abs"], "inf");
  EXPECT_EQ(j["rmse"], "inf");
  EXPECT_EQ(j["nonfinite_pixels"], 1);
  for (auto it = j.begin(); it != j.end(); ++it) EXPECT_FALSE(it->is_null()) << it.key();
  EXPECT_EQ(ts::countNonFinitePixels({glm::vec4(INFINITY), glm::vec4(0.0f), glm::vec4(-NAN)}), 2u);
  // The heat map's error of such a pixel is infinite (white), not NaN.
  EXPECT_TRUE(std::isinf(ts::errorMap(broken, ref)[0]));
}

}  // namespace
