// Tests of env-hier (engine/sampling/env/env_hier.h): hand-worked tables, pyramid layout, round trips, pdf
// consistency, chi-square on the shared hard environments, zero regions, black maps and a 1e6 sun.
#include "engine/sampling/env/env_hier.h"

#include "engine/core/error.h"
#include "tests/sampling/env_technique_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

using namespace iblx;

TEST_CASE("env-hier: hand-worked 4x2 table") {
  const EnvHierData data = buildEnvHier(test::handWorkedImage());
  REQUIRE(data.width == 4);
  REQUIRE(data.height == 2);
  // Finest 4x4 (rows 2 and 3 padding): weight * pi/2 = {pi/2, 0, 3pi/2, 0; pi, pi, pi, pi; 0...}; 2x2:
  // {5pi/2, 7pi/2; 0, 0}; root 6pi.
  REQUIRE(data.levels.size() == 3);
  const auto level = [&](int k) {
    const EnvHierLevel& l = data.levels[std::size_t(k)];
    return std::vector<uint32_t>{l.offset, l.width, l.height, l.pad};
  };
  CHECK(level(0) == std::vector<uint32_t>{0, 1, 1, 0});
  CHECK(level(1) == std::vector<uint32_t>{1, 2, 2, 0});
  CHECK(level(2) == std::vector<uint32_t>{5, 4, 4, 0});
  const double p = kPi;
  const std::vector<double> nodes{6 * p, 2.5 * p, 3.5 * p, 0, 0,  // root, level 1
                                  p / 2, 0,       1.5 * p, 0, p, p, p, p, 0, 0, 0, 0, 0, 0, 0, 0};
  REQUIRE(data.nodes.size() == nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) CHECK(data.nodes[i] == float(nodes[i]));

  const EnvHierSampler sampler(data);
  // u = (0.5, 0.2): root -> 2x2: pLeft = (5/2)/6 = 5/12, u.x >= pLeft: right, u.x = (1/12)/(7/12) = 1/7,
  // prob = 7/12; the right column's pTop = 1 (its lower node is padding): top, u.y stays 0.2. Node (1,0) ->
  // columns {2, 3}: pLeft = (3/2 + 1)/(7/2) = 5/7, u.x < pLeft: left, u.x = 1/5, prob = 5/12; rows of column
  // 2: pTop = (3/2)/(5/2) = 3/5, u.y = 0.2 < pTop: top, u.y = 1/3, prob = 1/4.
  // pdf = (1/4) / (pi/2) = 1 / (2 pi), the same as env-cdf: both are exactly proportional to the texel
  // weight.
  const EnvSample s = sampler.sample({0.5, 0.2});
  CHECK(s.texel == glm::ivec2(2, 0));
  CHECK(sampler.texelProbability(2, 0) == doctest::Approx(0.25).epsilon(1e-6));
  CHECK(s.pdfSolidAngle == doctest::Approx(1.0 / (2.0 * kPi)).epsilon(1e-6));
  // t = (1/5, 1/3): phi = 2 pi (2 + 1/5) / 4 = 1.1 pi; cos(theta) = 1 - 1/3.
  const double cosTheta = 2.0 / 3.0, sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
  const glm::dvec3 expected(sinTheta * std::cos(1.1 * kPi), cosTheta, sinTheta * std::sin(1.1 * kPi));
  CHECK(glm::length(s.direction - expected) < 1e-6);
  CHECK(sampler.pdf(s.direction) == s.pdfSolidAngle);
  const auto u = sampler.invert(s.direction);
  REQUIRE(u);
  CHECK(u->x == doctest::Approx(0.5).epsilon(1e-6));
  CHECK(u->y == doctest::Approx(0.2).epsilon(1e-6));
  // Zero texels (1, 0) and (3, 0) have probability 0; texel (0, 1): weight 2 -> pdf 2 / (6 pi).
  CHECK(sampler.texelProbability(1, 0) == 0.0f);
  CHECK(sampler.texelProbability(3, 0) == 0.0f);
  CHECK_FALSE(sampler.invert(texelToDirection(1, 0, {0.5, 0.5}, 4, 2)));
  CHECK(sampler.pdf(texelToDirection(0, 1, {0.5, 0.5}, 4, 2)) ==
        doctest::Approx(1.0 / (3.0 * kPi)).epsilon(1e-6));
  double total = 0.0;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) total += sampler.texelProbability(x, y);
  CHECK(total == doctest::Approx(1.0).epsilon(1e-6));
}

TEST_CASE("env-hier: hand-worked 3x1 table with padding") {
  // Weights {1, 2, 3}, Omega = 4 pi / 3 each; finest level 4x4 = {4pi/3, 8pi/3, 4pi, 0; 0...} (padding).
  const EnvImage img = makeEnv(3, 1, [](int x, int, double, double) {
    const double v = x + 1.0;
    return std::array<double, 3>{v, v, v};
  });
  const EnvHierData data = buildEnvHier(img);
  REQUIRE(data.levels.size() == 3);
  CHECK(data.levels.back().width == 4);
  CHECK(data.levels.back().height == 4);
  CHECK(data.nodes.back() == 0.0f);
  const EnvHierSampler sampler(data);
  // u.x = 0.75: root pLeft = 4pi / 8pi = 1/2 -> right, u.x = 1/2, prob 1/2, pTop = 1 (padding below); node
  // (1, 0) -> {2, 3 (padding)}: pLeft = 1 -> texel 2 with u.x = 1/2; pdf = (1/2) / (4 pi / 3) = 3 / (8 pi)
  // = 3 / (sum of weight * Omega).
  const EnvSample s = sampler.sample({0.75, 0.5});
  CHECK(s.texel == glm::ivec2(2, 0));
  CHECK(s.pdfSolidAngle == doctest::Approx(3.0 / (8.0 * kPi)).epsilon(1e-6));
  for (const glm::dvec2 u : test::uniformPoints(1000, 3)) CHECK(sampler.sample(u).texel.x < 3);
}

TEST_CASE("env-hier: pyramid layout on hard envs") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvHierData d = buildEnvHier(env.image);
    REQUIRE(!d.levels.empty());
    CHECK(d.levels.front().width == 1);
    CHECK(d.levels.front().height == 1);
    const EnvHierLevel& finest = d.levels.back();
    CHECK(finest.width == std::max(std::bit_ceil(unsigned(d.width)), std::bit_ceil(unsigned(d.height))));
    CHECK(finest.height == finest.width);
    std::size_t offset = 0;
    for (const EnvHierLevel& l : d.levels) {
      CHECK(l.offset == offset);
      CHECK(l.pad == 0);
      offset += std::size_t(l.width) * l.height;
    }
    CHECK(d.nodes.size() == offset);
    // Padding is zero, and each node is the sum of its children (rounded to float).
    for (uint32_t y = 0; y < finest.height; ++y)
      for (uint32_t x = 0; x < finest.width; ++x)
        if (int(x) >= d.width || int(y) >= d.height)
          CHECK(d.nodes[finest.offset + y * finest.width + x] == 0.0f);
    for (std::size_t k = 0; k + 1 < d.levels.size(); ++k) {
      const EnvHierLevel &c = d.levels[k], &f = d.levels[k + 1];
      const uint32_t kx = f.width / c.width, ky = f.height / c.height;
      for (uint32_t y = 0; y < c.height; ++y)
        for (uint32_t x = 0; x < c.width; ++x) {
          double sum = 0.0;
          for (uint32_t j = 0; j < ky; ++j)
            for (uint32_t i = 0; i < kx; ++i) sum += d.nodes[f.offset + (ky * y + j) * f.width + kx * x + i];
          CHECK(d.nodes[c.offset + y * c.width + x] == doctest::Approx(sum).epsilon(1e-5));
        }
    }
  }
}

TEST_CASE("env-hier: a texel's probability is its weight over the total (the shares telescope)") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvHierSampler sampler(buildEnvHier(env.image));
    const EnvHierData& d = sampler.data();
    const EnvHierLevel& finest = d.levels.back();
    const double total = d.nodes[0];
    for (int y = 0; y < d.height; ++y)
      for (int x = 0; x < d.width; ++x) {
        const double weight = d.nodes[finest.offset + std::size_t(y) * finest.width + std::size_t(x)];
        // float shares multiplied over up to 8 levels: a few ulps per level
        CHECK(double(sampler.texelProbability(x, y)) == doctest::Approx(weight / total).epsilon(1e-5));
      }
  }
}

TEST_CASE("env-hier: sample -> invert round trip and pdf consistency on hard envs") {
  test::checkRoundTripOnHardEnvs<EnvHierSampler>(buildEnvHier);
}

TEST_CASE("env-hier: chi2 on hard envs") {
  test::checkChi2OnHardEnvs<EnvHierSampler>(buildEnvHier, "env-hier");
}

TEST_CASE("env-hier: zero-weight texels are never sampled") {
  test::checkZeroWeightTexelsNeverSampled<EnvHierSampler>(buildEnvHier);
}

TEST_CASE("env-hier: all-zero image samples the sphere uniformly") {
  test::checkAllZeroImageIsUniform<EnvHierSampler>(buildEnvHier, "env-hier");
}

TEST_CASE("env-hier: 1e6 sun with a zero half") {
  test::checkSunWithZeroHalf<EnvHierSampler>(buildEnvHier);
}

TEST_CASE("env-hier: rejects invalid images") {
  test::checkBuildRejectsInvalidImages(buildEnvHier);
  EnvHierData bad = buildEnvHier(constantEnv(8, 4, 1.0f));
  bad.nodes.pop_back();
  CHECK_THROWS_AS(EnvHierSampler{bad}, Error);
  bad = buildEnvHier(constantEnv(8, 4, 1.0f));
  bad.levels.erase(bad.levels.begin() + 1);
  CHECK_THROWS_AS(EnvHierSampler{bad}, Error);
}

TEST_CASE("env-hier: the guide only skips levels (same warp as the descent from the root)") {
  // Wide, tall (padded to a square along x), padded and 1-texel maps next to the hard ones.
  std::vector<test::NamedEnv> envs = test::samplerTestEnvs();
  for (const auto& [w, h] : {std::pair{8, 32}, std::pair{3, 13}, std::pair{1, 1}, std::pair{16, 1}})
    envs.push_back({std::to_string(w) + "x" + std::to_string(h) + " random",
                    makeEnv(w, h, [](int x, int y, double, double) {
                      const double v = 0.1 + double((x * 7919 + y * 104729) % 97);
                      return std::array<double, 3>{v, v, v};
                    })});
  for (const auto& env : envs) {
    CAPTURE(env.name);
    const EnvHierData data = buildEnvHier(env.image);
    const EnvHierSampler fromRoot(data, 1);  // one cell: every descent starts at the root
    const EnvHierSampler guided(data);
    const EnvHierGpuData& gpu = guided.gpuData();
    CHECK(fromRoot.gpuData().guideNodes.size() == 1);
    CHECK(fromRoot.gpuData().guideNodes[0] == 0);
    // The rectangles are exact float sets and every cell lies inside its start node's, so starting there
    // changes nothing: the same texel, pdf and direction, bit for bit, at the corners of every cell and at
    // random points.
    const double g = double(gpu.guideSize);
    std::size_t deeperThanRoot = 0;
    const auto same = [&](glm::dvec2 u) {
      const EnvSample a = fromRoot.sample(u), b = guided.sample(u);
      return a.texel == b.texel && a.pdfSolidAngle == b.pdfSolidAngle && a.direction == b.direction;
    };
    std::size_t differing = 0;
    for (uint32_t cy = 0; cy < gpu.guideSize; ++cy)
      for (uint32_t cx = 0; cx < gpu.guideSize; ++cx) {
        deeperThanRoot += gpu.guideNodes[std::size_t(cy) * gpu.guideSize + cx] != 0 ? 1 : 0;
        const glm::dvec2 lo(cx / g, cy / g);
        const glm::dvec2 hi((cx + 1) / g - 0x1p-24, (cy + 1) / g - 0x1p-24);  // the cell's last float u
        for (const glm::dvec2 u : {lo, hi, glm::dvec2(lo.x, hi.y), glm::dvec2(hi.x, lo.y)})
          differing += !same(u);
      }
    if (data.levels.size() > 3) CHECK(deeperThanRoot > gpu.guideNodes.size() / 2);  // the guide skips levels
    for (const glm::dvec2 u : test::uniformPoints(20000, 11)) differing += !same(u);
    CHECK(differing == 0);
  }
}
