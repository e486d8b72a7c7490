// Checks shared by the env-cdf and env-hier tests, templated on the sampler type and its table builder.
#pragma once

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/io/env_image.h"
#include "engine/io/latlong_texel.h"
#include "engine/core/sphere_mapping.h"
#include "tests/support/chi2.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace iblx::test {

inline constexpr std::size_t kChi2Samples = 200000;

// 4 x 2 map with weights {1, 0, 3, 0} on the top row and {2, 2, 2, 2} on the bottom row; both rows subtend
// Omega = pi/2 per texel, so the row weights are 2 pi and 4 pi (total 6 pi).
inline EnvImage handWorkedImage() {
  return makeEnv(4, 2, [](int x, int y, double, double) {
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

template <typename Sampler>
Chi2Result runChi2(const Sampler& sampler, const std::string& label, int testCount, uint64_t seed) {
  std::vector<glm::dvec3> directions;
  directions.reserve(kChi2Samples);
  for (const glm::dvec2 u : uniformPoints(kChi2Samples, seed))
    directions.push_back(sampler.sample(u).direction);
  Chi2Options options;
  options.label = label;
  options.testCount = testCount;
  const auto batchPdf = [&](std::span<const glm::dvec3> w) {
    std::vector<double> p(w.size());
    for (std::size_t i = 0; i < w.size(); ++i) p[i] = sampler.pdf(w[i]);
    return p;
  };
  return chi2Test(directions, batchPdf, options);
}

// How a round trip sample(u) -> invert -> sample is judged: by u itself, or by the direction it reaches again
// (for a warp that reaches some texels from two places, such as env-ot's split sun, where invert() returns
// one).
enum class RoundTrip { SameU, SameDirection };

template <typename Sampler, typename Build>
void checkRoundTripOnHardEnvs(Build build, RoundTrip judge = RoundTrip::SameU) {
  for (const auto& env : samplerTestEnvs()) {
    CAPTURE(env.name);
    const Sampler sampler(build(env.image));
    int boundary = 0;
    for (const glm::dvec2 u : uniformPoints(20000, 5)) {
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
      const EnvSample again = sampler.sample(*back);
      CHECK(again.texel == s.texel);
      if (judge == RoundTrip::SameU) {
        CHECK(std::abs(back->x - double(toGpuU(u.x))) < 1e-6);
        CHECK(std::abs(back->y - double(toGpuU(u.y))) < 1e-6);
      } else {
        CHECK(glm::length(again.direction - s.direction) < 1e-4);
      }
    }
    CHECK(boundary <= 2);
  }
}

// labelPrefix names the chi2 runs ("<labelPrefix>-<env name>").
template <typename Sampler, typename Build>
void checkChi2OnHardEnvs(Build build, const std::string& labelPrefix) {
  const auto envs = samplerTestEnvs();
  uint64_t seed = 100;
  for (const auto& env : envs) {
    CAPTURE(env.name);
    const Sampler sampler(build(env.image));
    const Chi2Result r = runChi2(sampler, labelPrefix + "-" + env.name, int(envs.size()), seed++);
    INFO(r.message);
    CHECK(r.passed);
    CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-3));
  }
}

template <typename Sampler, typename Build>
void checkZeroWeightTexelsNeverSampled(Build build) {
  for (const auto& env : samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvImage& img = env.image;
    const Sampler sampler(build(img));
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if (img.weight(x, y) == 0.0) CHECK(sampler.texelProbability(x, y) == 0.0f);
    for (const glm::dvec2 u : uniformPoints(20000, 9)) {
      const EnvSample s = sampler.sample(u);
      CHECK(img.weight(s.texel.x, s.texel.y) > 0.0);
      CHECK(sampler.pdf(s.direction) > 0.0);
    }
  }
}

// labelPrefix names the chi2 run ("<labelPrefix>-black").
template <typename Sampler, typename Build>
void checkAllZeroImageIsUniform(Build build, const std::string& labelPrefix) {
  WarningCounter warnings;
  const EnvImage black = constantEnv(50, 25, 0.0f);
  const Sampler sampler(build(black));
  CHECK(warnings.count == 1);
  for (const glm::dvec2 u : uniformPoints(2000, 17)) {
    const EnvSample s = sampler.sample(u);
    CHECK(s.pdfSolidAngle == doctest::Approx(1.0 / (4.0 * kPi)).epsilon(1e-5));
  }
  const Chi2Result r = runChi2(sampler, labelPrefix + "-black", 1, 18);
  INFO(r.message);
  CHECK(r.passed);
  CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-3));
}

template <typename Sampler, typename Build>
void checkSunWithZeroHalf(Build build) {
  // Larger than the chi2 fixtures, so the sky's share of the sun row is near the float spacing of the CDF.
  const EnvImage img = sunAndZeroHalf(512, 256);
  const Sampler sampler(build(img));
  // Probability of the two sun texels read from the tables: about 97 % of the mass.
  const int sunX = img.width / 3, sunY = img.height / 4;
  const double sunProb =
      double(sampler.texelProbability(sunX, sunY)) + sampler.texelProbability(sunX + 1, sunY);
  CHECK(sunProb > 0.9);
  int sunHits = 0;
  for (const glm::dvec2 u : uniformPoints(50000, 21)) {
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

// The image checks only; each test adds its own malformed-table checks on the sampler constructor.
template <typename Build>
void checkBuildRejectsInvalidImages(Build build) {
  EnvImage img = constantEnv(8, 4, 1.0f);
  img.rgb[5] = -1.0f;
  CHECK_THROWS_AS(build(img), Error);
  img.rgb[5] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(build(img), Error);
  img.rgb[5] = std::numeric_limits<float>::infinity();
  CHECK_THROWS_AS(build(img), Error);
  img.rgb.pop_back();
  CHECK_THROWS_AS(build(img), Error);
  CHECK_THROWS_AS(build(EnvImage{}), Error);
}

}  // namespace iblx::test
