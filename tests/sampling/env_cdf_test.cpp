// Tests of env-cdf (engine/sampling/env/env_cdf.h): hand-worked table, table invariants, round trips, pdf
// consistency, chi-square on the shared hard environments, zero regions, black maps and a 1e6 sun.
#include "engine/sampling/env/env_cdf.h"

#include "engine/core/error.h"
#include "tests/sampling/env_technique_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace iblx;

TEST_CASE("env-cdf: hand-worked 4x2 table") {
  const EnvCdfData data = buildEnvCdf(test::handWorkedImage());
  REQUIRE(data.width == 4);
  REQUIRE(data.height == 2);
  // Marginal: {0, 2pi / 6pi, 1}; conditionals: {0, 1/4, 1/4, 1, 1} and {0, 1/4, 1/2, 3/4, 1}.
  const std::vector<float> marginal{0.0f, 1.0f / 3.0f, 1.0f};
  const std::vector<float> conditional{0.0f, 0.25f, 0.25f, 1.0f, 1.0f, 0.0f, 0.25f, 0.5f, 0.75f, 1.0f};
  CHECK(data.marginalCdf == marginal);
  CHECK(data.conditionalCdf == conditional);

  const EnvCdfSampler sampler(data);
  // u = (0.5, 0.2): row 0 (0.2 < 1/3), t.y = 0.2 / (1/3) = 0.6; column 2 (first entry > 0.5 is cdf[3] = 1),
  // t.x = (0.5 - 0.25) / 0.75 = 1/3; P = 1/3 * 3/4 = 1/4 and pdf = P / (pi/2) = 1 / (2 pi) = 3 / (6 pi).
  const EnvSample s = sampler.sample({0.5, 0.2});
  CHECK(s.texel == glm::ivec2(2, 0));
  CHECK(s.pdfSolidAngle == doctest::Approx(1.0 / (2.0 * kPi)).epsilon(1e-6));
  // phi = 2 pi (2 + 1/3) / 4 = 7 pi / 6; cos(theta) = 1 + 0.6 (0 - 1) = 0.4.
  const double sinTheta = std::sqrt(1.0 - 0.16);
  const glm::dvec3 expected(sinTheta * std::cos(7.0 * kPi / 6.0), 0.4, sinTheta * std::sin(7.0 * kPi / 6.0));
  CHECK(glm::length(s.direction - expected) < 1e-6);
  CHECK(sampler.pdf(s.direction) == s.pdfSolidAngle);
  const auto u = sampler.invert(s.direction);
  REQUIRE(u);
  CHECK(u->x == doctest::Approx(0.5).epsilon(1e-6));
  CHECK(u->y == doctest::Approx(0.2).epsilon(1e-6));
  // u.x = 1/4 lands exactly on the zero-width bin of texel 1: it is skipped (texel 2, t.x = 0).
  CHECK(sampler.sample({0.25, 0.2}).texel == glm::ivec2(2, 0));
  // pdf elsewhere: zero texel (1, 0); texel (0, 1) has weight 2 -> 2 / (6 pi).
  CHECK(sampler.pdf(texelToDirection(1, 0, {0.5, 0.5}, 4, 2)) == 0.0);
  CHECK_FALSE(sampler.invert(texelToDirection(1, 0, {0.5, 0.5}, 4, 2)));
  CHECK(sampler.pdf(texelToDirection(0, 1, {0.5, 0.5}, 4, 2)) ==
        doctest::Approx(1.0 / (3.0 * kPi)).epsilon(1e-6));
}

TEST_CASE("env-cdf: tables are valid float CDFs on hard envs") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvCdfData d = buildEnvCdf(env.image);
    const int w = d.width, h = d.height;
    REQUIRE(d.marginalCdf.size() == std::size_t(h + 1));
    REQUIRE(d.conditionalCdf.size() == std::size_t(h) * std::size_t(w + 1));
    CHECK(d.marginalCdf.front() == 0.0f);
    CHECK(d.marginalCdf.back() == 1.0f);
    for (int y = 0; y < h; ++y) CHECK(d.marginalCdf[std::size_t(y + 1)] >= d.marginalCdf[std::size_t(y)]);
    for (int y = 0; y < h; ++y) {
      const float* c = d.conditionalCdf.data() + std::size_t(y) * std::size_t(w + 1);
      CHECK(c[0] == 0.0f);
      CHECK(c[w] == 1.0f);
      for (int x = 0; x < w; ++x) CHECK(c[x + 1] >= c[x]);
    }
  }
}

// The bin of u in a CDF by a plain search over all bins: the answer the guide tables must reproduce.
static int plainBin(const float* cdf, int n, float u) {
  return int(std::upper_bound(cdf + 1, cdf + n + 1, u) - cdf) - 1;
}

TEST_CASE("env-cdf: guided search finds the same bin as a full search") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvCdfData d = buildEnvCdf(env.image);
    const EnvCdfSampler sampler(d);
    const int rowCells = d.rowGuideCells;
    CHECK(d.marginalGuide.size() == std::size_t(rowCells));
    // Every CDF entry, its float neighbours and every cell boundary with its neighbours: the places where an
    // off-by-one in the guide would show. The sampled row must be the full search's row.
    std::vector<float> probes;
    for (float c : d.marginalCdf)
      probes.insert(probes.end(), {c, std::nextafter(c, 0.0f), std::nextafter(c, 1.0f)});
    for (int k = 0; k <= rowCells; ++k) {
      const float b = float(k) / float(rowCells);
      probes.insert(probes.end(), {b, std::nextafter(b, 0.0f), std::nextafter(b, 1.0f)});
    }
    for (float uy : probes) {
      if (!(uy >= 0.0f && uy < 1.0f)) continue;
      const int expectedRow = plainBin(d.marginalCdf.data(), d.height, uy);
      const EnvSample s = sampler.sample({0.5, double(uy)});
      REQUIRE(s.texel.y == expectedRow);
      // Columns of that row, probed the same way.
      const float* c = d.conditionalCdf.data() + std::size_t(expectedRow) * std::size_t(d.width + 1);
      for (int x = 0; x <= d.width; x += std::max(1, d.width / 16)) {
        for (float ux : {c[x], std::nextafter(c[x], 0.0f), std::nextafter(c[x], 1.0f)}) {
          if (!(ux >= 0.0f && ux < 1.0f)) continue;
          REQUIRE(sampler.sample({double(ux), double(uy)}).texel.x == plainBin(c, d.width, ux));
        }
      }
    }
  }
}

TEST_CASE("env-cdf: every guide cell holds exactly the bins of its u range, at any map size") {
  // lo = the bin of u = k/G, hi = the bin of the largest float below (k+1)/G, for every cell of the
  // marginal's guide and of every row's; sizes just above a power of two (the guide then has fewer cells per
  // bin).
  auto envs = test::samplerTestEnvs();
  envs.push_back({"sun-zero-17x9", sunAndZeroHalf(17, 9)});
  envs.push_back({"smooth-33x17", smoothSky(33, 17)});
  for (const auto& env : envs) {
    CAPTURE(env.name);
    const EnvCdfData d = buildEnvCdf(env.image);
    CHECK(d.rowGuideCells <= kEnvCdfRowCellsPerBin * d.height);
    CHECK(2 * d.rowGuideCells > kEnvCdfRowCellsPerBin * d.height);
    CHECK(d.columnGuideCells <= kEnvCdfColumnCellsPerBin * d.width);
    CHECK(d.columnGuideCells >= d.width);
    const auto checkGuide = [](const float* cdf, int n, const std::uint32_t* guide, int cells) {
      int wrong = 0;
      for (int k = 0; k < cells; ++k) {
        const float start = float(k) / float(cells), end = std::nextafter(float(k + 1) / float(cells), 0.0f);
        const int lo = int(guide[k] & 0xffffu), hi = int(guide[k] >> 16);
        wrong += lo != plainBin(cdf, n, start) || hi != plainBin(cdf, n, end);
      }
      return wrong;
    };
    CHECK(checkGuide(d.marginalCdf.data(), d.height, d.marginalGuide.data(), d.rowGuideCells) == 0);
    int wrongRows = 0;
    for (int y = 0; y < d.height; ++y)
      wrongRows += checkGuide(d.conditionalCdf.data() + std::size_t(y) * std::size_t(d.width + 1), d.width,
                              d.conditionalGuide.data() + std::size_t(y) * std::size_t(d.columnGuideCells),
                              d.columnGuideCells) != 0;
    CHECK(wrongRows == 0);
  }
}

TEST_CASE("env-cdf: sample -> invert round trip and pdf consistency on hard envs") {
  test::checkRoundTripOnHardEnvs<EnvCdfSampler>(buildEnvCdf);
}

TEST_CASE("env-cdf: chi2 on hard envs") {
  test::checkChi2OnHardEnvs<EnvCdfSampler>(buildEnvCdf, "env-cdf");
}

TEST_CASE("env-cdf: zero-weight texels are never sampled") {
  test::checkZeroWeightTexelsNeverSampled<EnvCdfSampler>(buildEnvCdf);
}

TEST_CASE("env-cdf: all-zero image samples the sphere uniformly") {
  test::checkAllZeroImageIsUniform<EnvCdfSampler>(buildEnvCdf, "env-cdf");
}

TEST_CASE("env-cdf: 1e6 sun with a zero half") {
  test::checkSunWithZeroHalf<EnvCdfSampler>(buildEnvCdf);
}

TEST_CASE("env-cdf: rejects invalid images") {
  test::checkBuildRejectsInvalidImages(buildEnvCdf);
  EnvCdfData bad = buildEnvCdf(constantEnv(8, 4, 1.0f));
  bad.marginalCdf.pop_back();
  CHECK_THROWS_AS(EnvCdfSampler{bad}, Error);
}
