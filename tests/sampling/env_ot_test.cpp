// Tests of env-ot (engine/sampling/env/env_ot.h): the texel-exact probabilities, the pieces tiling the
// texels, the grid's rows keeping the OT map's masses, round trips through invert(), chi-square on the shared
// hard environments, zero regions, black maps and a 1e6 sun.
#include "engine/sampling/env/env_ot.h"

#include "engine/core/error.h"
#include "engine/io/synthetic_envs.h"
#include "tests/sampling/env_technique_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

using namespace iblx;

namespace {

// The hard environments plus a map large enough for a 128 grid over 256 x 128 texels (two texel rows per
// density row, several texels per cell) and one whose density rows are finer than its texel rows (50 x 25
// under a 32 grid).
std::vector<test::NamedEnv> meshTestEnvs() {
  std::vector<test::NamedEnv> envs = test::samplerTestEnvs();
  envs.push_back({"smooth-256x128", smoothSky(256, 128)});
  return envs;
}

}  // namespace

TEST_CASE("env-ot: every texel's probability is its weight's share (texel-exact)") {
  for (const auto& env : meshTestEnvs()) {
    CAPTURE(env.name);
    const EnvImage& img = env.image;
    const EnvOtSampler sampler(buildEnvOt(img));
    const std::vector<double> weights = texelSamplingWeights(img, "test");
    double total = 0.0;
    for (const double w : weights) total += w;
    double worst = 0.0, weightedError = 0.0, sum = 0.0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const double expected = weights[std::size_t(y) * img.width + x] / total;
        const double p = sampler.texelProbability(x, y);
        sum += p;
        if (expected == 0.0) {
          CHECK(p == 0.0);
          continue;
        }
        worst = std::max(worst, std::abs(p / expected - 1.0));
        weightedError += std::abs(p - expected);
        // The pdf of the texel is the probability the tables give it, over its solid angle.
        const double omega = latLongTexelSolidAngle(y, img.width, img.height);
        CHECK(sampler.data().texelPdf[std::size_t(y) * img.width + x] * omega ==
              doctest::Approx(p).epsilon(1e-6));
      }
    CHECK(sum == doctest::Approx(1.0).epsilon(1e-6));
    // Float CDFs: a piece's probability is off by about 2^-24 over its share of its row; the worst are the
    // polar texels of the 256 x 128 map, whose share of their row is about 1e-5 (measured 0.6 %).
    CHECK(worst < 2e-2);
    CHECK(weightedError < 1e-4);
  }
}

TEST_CASE("env-ot: the map's pieces tile every texel they cover") {
  for (const auto& env : meshTestEnvs()) {
    CAPTURE(env.name);
    const EnvImage& img = env.image;
    const EnvOtSampler sampler(buildEnvOt(img));
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const double coverage = sampler.texelCoverage(x, y);
        if (coverage == 0.0) continue;  // no smooth weight: every piece was dropped
        // Corners are stored as 16-bit fractions of the texel, so the areas sum to 1 up to about 1e-4.
        CHECK(coverage == doctest::Approx(1.0).epsilon(2e-3));
      }
    // Only texels that lie wholly inside one cell are single pieces; the others are cut by the cells' edges.
    std::size_t triangles = 0;
    for (const glm::uvec4& piece : sampler.data().pieces) triangles += (piece.x & kEnvOtTrianglePiece) != 0;
    CHECK(triangles > 0);
  }
}

TEST_CASE("env-ot: the grid's rows keep the OT map's equal masses on a smooth map") {
  const EnvOtSampler sampler(buildEnvOt(smoothSky(256, 128)));
  const EnvOtData& d = sampler.data();
  REQUIRE(d.rows == d.grid);  // no sun split on a smooth sky
  double worst = 0.0;
  for (int j = 0; j < d.rows; ++j)
    worst = std::max(
        worst, std::abs(double(d.rowCdf[std::size_t(j) + 1] - d.rowCdf[std::size_t(j)]) * d.grid - 1.0));
  // The solver's residual (targetL1 1e-3 of the mass) and the density floor, not a texel CDF's row masses,
  // which on this sky vary by a factor of about 30 from the horizon to the poles.
  CHECK(worst < 0.05);
}

TEST_CASE("env-ot: sample -> invert -> sample round trip and pdf consistency on hard envs") {
  // A sun texel is reached from the sun's row and from the map's pieces: invert() finds one of them, so the
  // round trip compares directions rather than u.
  test::checkRoundTripOnHardEnvs<EnvOtSampler>([](const EnvImage& e) { return buildEnvOt(e); },
                                               test::RoundTrip::SameDirection);
}

TEST_CASE("env-ot: chi2 on hard envs") {
  test::checkChi2OnHardEnvs<EnvOtSampler>([](const EnvImage& e) { return buildEnvOt(e); }, "env-ot");
}

TEST_CASE("env-ot: zero-weight texels are never sampled") {
  test::checkZeroWeightTexelsNeverSampled<EnvOtSampler>([](const EnvImage& e) { return buildEnvOt(e); });
}

TEST_CASE("env-ot: all-zero image samples the sphere uniformly") {
  test::checkAllZeroImageIsUniform<EnvOtSampler>([](const EnvImage& e) { return buildEnvOt(e); }, "env-ot");
}

TEST_CASE("env-ot: 1e6 sun with a zero half") {
  test::checkSunWithZeroHalf<EnvOtSampler>([](const EnvImage& e) { return buildEnvOt(e); });
  // The sun is split off into its own row of the same CDFs.
  const EnvOtData d = buildEnvOt(sunAndZeroHalf(512, 256));
  CHECK(d.rows == d.grid + 1);
  CHECK(d.sunTexels > 0);
}

TEST_CASE("env-ot: rejects invalid images and mis-sized tables") {
  test::checkBuildRejectsInvalidImages([](const EnvImage& e) { return buildEnvOt(e); });
  const EnvOtData good = buildEnvOt(smoothSky(64, 32));
  EnvOtData bad = good;
  bad.rowCdf.pop_back();
  CHECK_THROWS_AS(EnvOtSampler{bad}, Error);
  bad = good;
  bad.pieces.front().x = 64u * 32u;  // a texel outside the map
  CHECK_THROWS_AS(EnvOtSampler{bad}, Error);
  bad = good;
  bad.pieceGuide.pop_back();
  CHECK_THROWS_AS(EnvOtSampler{bad}, Error);
}
