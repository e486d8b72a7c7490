// Tests of env-cdf (engine/sampling/env_cdf.h): hand-worked table, table invariants, round trips, pdf
// consistency, chi-square on the shared hard environments, zero regions, black maps and a 1e6 sun.
#include "engine/sampling/env_cdf.h"

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "tests/support/chi2.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace iblx;

namespace {

constexpr std::size_t kChi2Samples = 200000;

// 4 x 2 map with weights {1, 0, 3, 0} on the top row and {2, 2, 2, 2} on the bottom row; both rows subtend
// Omega = pi/2 per texel, so the row weights are 2 pi and 4 pi (total 6 pi).
EnvImage handWorkedImage() {
  return test::makeEnv(4, 2, [](int x, int y, double, double) {
    const double v = y == 0 ? std::vector<double>{1, 0, 3, 0}[std::size_t(x)] : 2.0;
    return std::array<double, 3>{v, v, v};
  });
}

// Silences the "black environment" warning and counts it.
struct WarningCounter {
  int count = 0;
  LogSink previous;
  WarningCounter() : previous(setWarningSink([this](const std::string&) { ++count; })) {}
  ~WarningCounter() { setWarningSink(previous); }
};

std::vector<double> batchPdf(const EnvCdfSampler& sampler, std::span<const glm::dvec3> directions) {
  std::vector<double> p(directions.size());
  for (std::size_t i = 0; i < directions.size(); ++i) p[i] = sampler.pdf(directions[i]);
  return p;
}

test::Chi2Result runChi2(const EnvCdfSampler& sampler, const std::string& label, int testCount,
                         uint64_t seed) {
  std::vector<glm::dvec3> directions;
  directions.reserve(kChi2Samples);
  for (const glm::dvec2 u : test::uniformPoints(kChi2Samples, seed))
    directions.push_back(sampler.sample(u).direction);
  test::Chi2Options options;
  options.label = label;
  options.testCount = testCount;
  return test::chi2Test(
      directions, [&](std::span<const glm::dvec3> w) { return batchPdf(sampler, w); }, options);
}

}  // namespace

TEST_CASE("env-cdf: hand-worked 4x2 table") {
  const EnvCdfData data = buildEnvCdf(handWorkedImage());
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

TEST_CASE("env-cdf: sample -> invert round trip and pdf consistency on hard envs") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvCdfSampler sampler(buildEnvCdf(env.image));
    int boundary = 0;
    for (const glm::dvec2 u : test::uniformPoints(20000, 5)) {
      const EnvSample s = sampler.sample(u);
      REQUIRE(s.pdfSolidAngle > 0.0);
      REQUIRE(std::isfinite(s.pdfSolidAngle));
      // A direction on a texel border may be located in the neighbour (measure zero); count those.
      if (directionToTexel(s.direction, env.image.width, env.image.height) != s.texel) {
        ++boundary;
        continue;
      }
      CHECK(sampler.pdf(s.direction) == s.pdfSolidAngle);  // same float operations, bit for bit
      const auto back = sampler.invert(s.direction);
      REQUIRE(back);
      CHECK(std::abs(back->x - double(toGpuU(u.x))) < 1e-6);
      CHECK(std::abs(back->y - double(toGpuU(u.y))) < 1e-6);
      CHECK(sampler.sample(*back).texel == s.texel);
    }
    CHECK(boundary <= 2);
  }
}

TEST_CASE("env-cdf: chi2 on hard envs") {
  const auto envs = test::samplerTestEnvs();
  uint64_t seed = 100;
  for (const auto& env : envs) {
    CAPTURE(env.name);
    const EnvCdfSampler sampler(buildEnvCdf(env.image));
    const test::Chi2Result r = runChi2(sampler, "env-cdf-" + env.name, int(envs.size()), seed++);
    INFO(r.message);
    CHECK(r.passed);
    CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-3));
  }
}

TEST_CASE("env-cdf: zero-weight texels are never sampled") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvImage& img = env.image;
    const EnvCdfSampler sampler(buildEnvCdf(img));
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if (img.weight(x, y) == 0.0) CHECK(sampler.texelProbability(x, y) == 0.0f);
    for (const glm::dvec2 u : test::uniformPoints(20000, 9)) {
      const EnvSample s = sampler.sample(u);
      CHECK(img.weight(s.texel.x, s.texel.y) > 0.0);
      CHECK(sampler.pdf(s.direction) > 0.0);
    }
  }
}

TEST_CASE("env-cdf: all-zero image samples the sphere uniformly") {
  WarningCounter warnings;
  const EnvImage black = test::constantEnv(50, 25, 0.0f);
  const EnvCdfSampler sampler(buildEnvCdf(black));
  CHECK(warnings.count == 1);
  for (const glm::dvec2 u : test::uniformPoints(2000, 17)) {
    const EnvSample s = sampler.sample(u);
    CHECK(s.pdfSolidAngle == doctest::Approx(1.0 / (4.0 * kPi)).epsilon(1e-5));
  }
  const test::Chi2Result r = runChi2(sampler, "env-cdf-black", 1, 18);
  INFO(r.message);
  CHECK(r.passed);
  CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-3));
}

TEST_CASE("env-cdf: 1e6 sun with a zero half") {
  // Larger than the chi2 fixtures, so the sky's share of the sun row is near the float spacing of the CDF.
  const EnvImage img = test::sunAndZeroHalf(512, 256);
  const EnvCdfSampler sampler(buildEnvCdf(img));
  // Probability of the two sun texels read from the tables: about 97 % of the mass.
  const int sunX = img.width / 3, sunY = img.height / 4;
  const double sunProb =
      double(sampler.texelProbability(sunX, sunY)) + sampler.texelProbability(sunX + 1, sunY);
  CHECK(sunProb > 0.9);
  int sunHits = 0;
  for (const glm::dvec2 u : test::uniformPoints(50000, 21)) {
    const EnvSample s = sampler.sample(u);
    REQUIRE(std::isfinite(s.direction.x));
    REQUIRE(std::isfinite(s.direction.y));
    REQUIRE(std::isfinite(s.direction.z));
    REQUIRE(std::isfinite(s.pdfSolidAngle));
    REQUIRE(s.pdfSolidAngle > 0.0);
    CHECK(s.direction.y > 0.0);  // never in the black lower half
    CHECK(sampler.pdf(s.direction) > 0.0);
    sunHits += img.weight(s.texel.x, s.texel.y) > 1.0;
  }
  CHECK(sunHits / 50000.0 == doctest::Approx(sunProb).epsilon(0.01));
  // Extreme u values stay finite too.
  for (const glm::dvec2 u : {glm::dvec2(0.0), glm::dvec2(1.0), glm::dvec2(std::nextafter(1.0, 0.0), 0.0)}) {
    const EnvSample s = sampler.sample(u);
    CHECK(std::isfinite(s.pdfSolidAngle));
    CHECK(s.pdfSolidAngle > 0.0);
  }
}

TEST_CASE("env-cdf: rejects invalid images") {
  EnvImage img = test::constantEnv(8, 4, 1.0f);
  img.rgb[5] = -1.0f;
  CHECK_THROWS_AS(buildEnvCdf(img), Error);
  img.rgb[5] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(buildEnvCdf(img), Error);
  img.rgb[5] = std::numeric_limits<float>::infinity();
  CHECK_THROWS_AS(buildEnvCdf(img), Error);
  img.rgb.pop_back();
  CHECK_THROWS_AS(buildEnvCdf(img), Error);
  CHECK_THROWS_AS(buildEnvCdf(EnvImage{}), Error);
  EnvCdfData bad = buildEnvCdf(test::constantEnv(8, 4, 1.0f));
  bad.marginalCdf.pop_back();
  CHECK_THROWS_AS(EnvCdfSampler{bad}, Error);
}
