// Tests of the sun / smooth split of the OT techniques (engine/sampling/env/env_ot_sun.h): weight is
// conserved, only texels above the cap are split off, the CDF and the per-texel lookup agree, and the split
// is what untangles the map of a sun-dominated environment (regression: the untangled map of the whole
// density misplaced a third of the mass).
#include "engine/sampling/env/env_ot_sun.h"

#include "engine/core/error.h"
#include "engine/io/latlong_texel.h"
#include "engine/ot/map.h"
#include "engine/ot/solver.h"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

using namespace iblx;

namespace {

// Texel weights of a sky of radiance 1 with a sun of radiance `sun` on texels (5, 3) and (6, 3) of W x H.
std::vector<double> skyWithSun(int width, int height, double sun) {
  std::vector<double> w(std::size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const bool isSun = y == 3 && (x == 5 || x == 6);
      w[std::size_t(y) * width + x] = (isSun ? sun : 1.0) * latLongTexelSolidAngle(y, width, height);
    }
  return w;
}

double sum(const std::vector<double>& v) {
  double s = 0.0;
  for (const double x : v) s += x;
  return s;
}

}  // namespace

TEST_CASE("ot sun split: the texels above the cap carry the excess; the rest is capped and the weight kept") {
  const int width = 32, height = 16;
  const std::vector<double> weights = skyWithSun(width, height, 1e5);
  const OtSunSplit split = splitOtSun(weights, width, height, 100.0);
  REQUIRE(split.texels.size() == 2);
  CHECK(split.texels[0] == 3u * width + 5u);
  CHECK(split.texels[1] == 3u * width + 6u);
  // The cap is 100 x the median radiance (1): each sun texel keeps 100 Omega, the sky is untouched.
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t t = std::size_t(y) * width + x;
      const bool isSun = y == 3 && (x == 5 || x == 6);
      CHECK(split.smoothWeights[t] ==
            doctest::Approx((isSun ? 100.0 : 1.0) * latLongTexelSolidAngle(y, width, height)).epsilon(1e-12));
    }
  const double total = sum(weights), smooth = sum(split.smoothWeights);
  CHECK(double(split.sunShare) == doctest::Approx((total - smooth) / total).epsilon(1e-6));
  CHECK(split.cdf.front() == 0.0f);
  CHECK(split.cdf.back() == 1.0f);
  // Equal sun texels in one row: half the sun part each, found by the per-row lookup.
  CHECK(split.texelProbability(5, 3) == doctest::Approx(0.5));
  CHECK(split.texelProbability(6, 3) == doctest::Approx(0.5));
  CHECK(split.texelProbability(7, 3) == 0.0f);
  CHECK(split.texelProbability(5, 4) == 0.0f);
  for (int y = 0; y < height; ++y)
    CHECK(split.rowFirst[std::size_t(y) + 1] - split.rowFirst[std::size_t(y)] == (y == 3 ? 2u : 0u));
}

TEST_CASE("ot sun split: nothing above the cap, a black half, clip 0 and bad input") {
  const int width = 16, height = 8;
  SUBCASE("a smooth map is not split") {
    const OtSunSplit split = splitOtSun(skyWithSun(width, height, 50.0), width, height, 100.0);
    CHECK(split.sunShare == 0.0f);
    CHECK(split.texelProbability(5, 3) == 0.0f);  // the placeholder entry has probability 0
  }
  SUBCASE("a sun below the minimum share is not split, and the weights stay whole") {
    const std::vector<double> weights = skyWithSun(width, height, 1e3);
    const OtSunSplit all = splitOtSun(weights, width, height, 100.0, 0.0);
    REQUIRE(all.sunShare > 0.0f);
    const OtSunSplit none = splitOtSun(weights, width, height, 100.0, double(all.sunShare) * 1.01);
    CHECK(none.sunShare == 0.0f);
    CHECK(none.smoothWeights == weights);
    CHECK(none.texelProbability(5, 3) == 0.0f);
  }
  SUBCASE("clip 0 disables the split") {
    const OtSunSplit split = splitOtSun(skyWithSun(width, height, 1e6), width, height, 0.0);
    CHECK(split.sunShare == 0.0f);
  }
  SUBCASE("the median ignores black texels, so a black half does not cap the sky to 0") {
    std::vector<double> weights = skyWithSun(width, height, 1e4);
    for (int y = height / 2; y < height; ++y)
      for (int x = 0; x < width; ++x) weights[std::size_t(y) * width + x] = 0.0;
    const OtSunSplit split = splitOtSun(weights, width, height, 100.0);
    CHECK(split.texels.size() == 2);
    CHECK(split.sunShare > 0.9f);
  }
  SUBCASE("mis-sized or negative weights are refused") {
    std::vector<double> weights = skyWithSun(width, height, 1.0);
    CHECK_THROWS_AS(splitOtSun(weights, width + 1, height), Error);
    weights[3] = -1.0;
    CHECK_THROWS_AS(splitOtSun(weights, width, height), Error);
  }
}

TEST_CASE("ot sun split: the map of the capped density twists far less than the whole one") {
  // A 1e6 sun on 2 texels of a 64 x 32 map, OT grid 32: the whole density's map twists around the sun.
  const int width = 64, height = 32, n = 32;
  const std::vector<double> weights = skyWithSun(width, height, 1e6);
  const OtMap whole = solveOtMap(otDensityFromWeights(weights, width, height, n), n);
  const OtSunSplit split = splitOtSun(weights, width, height);
  const OtMap smooth = solveOtMap(otDensityFromWeights(split.smoothWeights, width, height, n), n);
  REQUIRE(whole.converged);
  REQUIRE(smooth.converged);
  const auto samplerL1 = [n](const OtMap& map) {
    const std::vector<double> areas = otQuadAreas(untangleQuads(map.vertices, n), n);
    double l1 = 0.0;
    for (std::size_t c = 0; c < areas.size(); ++c)
      l1 += std::abs(areas[c] - map.density[c] / (double(n) * n));
    return l1;
  };
  const double wholeL1 = samplerL1(whole), smoothL1 = samplerL1(smooth);
  MESSAGE("sampler map L1: whole density " << wholeL1 << ", capped density " << smoothL1);
  CHECK(wholeL1 > 0.05);
  CHECK(smoothL1 < 0.1 * wholeL1);  // measured 0.041 against 0.71
}
