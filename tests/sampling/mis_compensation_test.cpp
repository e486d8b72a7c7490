// Tests of MIS compensation (engine/sampling/env/mis_compensation.h): the compensated weights, the
// constant-map fallback, and an env sampler built on it never sampling where the map is at or below its mean.
#include "engine/sampling/env/mis_compensation.h"

#include "engine/sampling/env/env_cdf.h"
#include "engine/io/latlong_texel.h"
#include "tests/support/chi2.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace iblx;

TEST_CASE("mis compensation: weights are max(m - mean, 0) and a constant map is left alone") {
  // Rows of 1, 2, 3, 4 (W = 8, H = 4): mean over the sphere = sum m Omega / 4 pi.
  const EnvImage img = makeEnv(8, 4, [](int, int y, double, double) {
    const double v = y + 1.0;
    return std::array<double, 3>{v, 2.0 * v, 3.0 * v};  // mean of R, G, B = 2 (y + 1)
  });
  double total = 0.0;
  for (int y = 0; y < 4; ++y) total += 8 * 2.0 * (y + 1) * latLongTexelSolidAngle(y, 8, 4);
  const double mean = total / (4.0 * kPi);
  const EnvImage out = misCompensated(img);
  REQUIRE(out.width == 8);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      CAPTURE(y);
      const double expected = std::max(2.0 * (y + 1) - mean, 0.0);
      CHECK(out.weight(x, y) == doctest::Approx(expected).epsilon(1e-6));
      const std::size_t i = 3 * out.index(x, y);
      CHECK(out.rgb[i] == out.rgb[i + 1]);  // grey
    }
  CHECK(out.weight(0, 0) == 0.0);  // the dimmest row is below the mean
  CHECK(out.weight(0, 3) > 0.0);

  const EnvImage constant = constantEnv(8, 4, 2.0f);
  CHECK(misCompensated(constant).rgb == constant.rgb);
}

TEST_CASE("mis compensation: the compensated env-cdf never samples at or below the mean") {
  const EnvImage sky = smoothSky(64, 32);
  const EnvImage compensated = misCompensated(sky);
  const EnvCdfSampler sampler(buildEnvCdf(compensated));
  std::size_t zeroWeightSamples = 0, samples = 0;
  for (const glm::dvec2 u : test::uniformPoints(20000, 5)) {
    const EnvSample s = sampler.sample(u);
    if (!(s.pdfSolidAngle > 0.0)) continue;
    ++samples;
    zeroWeightSamples += compensated.weight(s.texel.x, s.texel.y) == 0.0;
  }
  CHECK(samples > 19000);
  CHECK(zeroWeightSamples == 0);
  std::size_t compensatedAway = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) compensatedAway += compensated.weight(x, y) == 0.0 && sky.weight(x, y) > 0.0;
  CHECK(compensatedAway > 0);  // the test map has texels below its mean
}
