// Tests of warp composition over env-ot's unit square (engine/sampling/product/env_ot_product.h): env-ot's
// inverse per branch, chi-square of the composed sampler against its own pdf on the hard maps under GGX and
// Lambert lobes, and the split sun's two preimages.
#include "engine/sampling/product/env_ot_product.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"
#include "tests/sampling/env_technique_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace iblx {
namespace {

// A shading point: normal, view and lobe (GGX with Smith masking, or Lambert), in the environment frame.
struct Lobe {
  glm::dvec3 n, wo;
  double alpha = 0.0;  // 0: Lambert
  std::string name;
};

// f cos of the lobe towards wi (Walter, Marschner, Li & Torrance 2007, "Microfacet Models for Refraction
// through Rough Surfaces", eqs. 20, 33, 34, without Fresnel).
double fCos(const Lobe& lobe, glm::dvec3 wi) {
  const double ni = glm::dot(lobe.n, wi), no = glm::dot(lobe.n, lobe.wo);
  if (!(ni > 0.0) || !(no > 0.0)) return 0.0;
  if (lobe.alpha == 0.0) return ni / kPi;
  const double a2 = lobe.alpha * lobe.alpha, nh = glm::dot(lobe.n, glm::normalize(wi + lobe.wo));
  const double d = a2 / (kPi * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
  const auto g1 = [a2](double c) { return 2.0 * c / (c + std::sqrt(a2 + (1.0 - a2) * c * c)); };
  return d * g1(ni) * g1(no) / (4.0 * no);
}

// F_j as the GLSL's productPrepare computes it: f cos at the cell's cap direction closest to the mirror
// direction of wo.
std::vector<double> lobeAtCells(const EnvProductLevel& grid, const Lobe& lobe) {
  const glm::dvec3 mirror = 2.0 * glm::dot(lobe.n, lobe.wo) * lobe.n - lobe.wo;
  std::vector<double> f;
  for (const glm::vec4& c : grid.centers)
    f.push_back(fCos(lobe, glm::normalize(closestDirectionInCap(glm::dvec3(c), double(c.w), mirror))));
  return f;
}

std::vector<Lobe> testLobes() {
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, 0.8, 0.5));
  const glm::dvec3 tangent = glm::normalize(glm::cross(n, glm::dvec3(0, 0, 1)));
  const auto view = [&](double degrees) {
    const double t = degrees * kPi / 180.0;
    return std::cos(t) * n + std::sin(t) * tangent;
  };
  // alpha = 0.2: a glossy lobe whose head stays within the harness's integration. With alpha = 0.1 at 85
  // degrees the head's hottest cell has 370x its neighbours' pdf, and the part of its image that a texel edge
  // cuts into a sliver (0.002 in cos theta) falls between the 4 x 4 (or 16 x 16) sub-cells' midpoints: the
  // expected count of one cell came out 14 against 98 samples, where a 1500 x 1500 midpoint rule gives 80.
  // Each chi-square run costs about 1.4 s (the harness refines along every jump of the head's cells): a
  // grazing glossy view on every map, a Lambert one on the maps with a split sun.
  return {{n, view(85.0), 0.2, "ggx-85"}, {n, view(60.0), 0.0, "lambert-60"}};
}

}  // namespace

TEST_CASE("env-ot inverse: each branch's preimage maps back to the direction") {
  for (const auto& env : test::samplerTestEnvs()) {
    CAPTURE(env.name);
    const EnvOtSampler ot(buildEnvOt(env.image));
    const EnvOtData& d = ot.data();
    const EnvOtInverse inverse = buildEnvOtInverse(d);
    REQUIRE(inverse.texelFirst.size() == std::size_t(d.width) * d.height + 1);
    // q_map + q_sun is env-ot's pdf.
    for (std::size_t t = 0; t < d.texelPdf.size(); ++t) {
      const glm::vec2 q = inverse.branchPdf[t];
      CHECK(double(q.x + q.y) == doctest::Approx(double(d.texelPdf[t])).epsilon(1e-5));
    }
    int far = 0, otherU = 0, tested = 0;
    for (const glm::dvec2 u : test::uniformPoints(20000, 5)) {
      const EnvSample s = ot.sample(u);
      if (!(s.pdfSolidAngle > 0.0)) continue;
      const EnvOtPreimages pre = envOtPreimages(d, inverse, s.direction);
      const bool sunRow = d.rows > d.grid && toGpuU(u.y) >= d.rowCdf[std::size_t(d.grid)];
      const std::optional<glm::dvec2>& back = sunRow ? pre.sun : pre.map;
      REQUIRE(back.has_value());
      ++tested;
      // The preimage found samples the direction again; it is u itself unless a texel holds several pieces
      // that the direction borders (a piece's edge), where the neighbour's u maps to the same direction.
      const EnvSample again = ot.sample(*back);
      far += glm::length(again.direction - s.direction) > 1e-4;
      otherU += glm::length(*back - glm::dvec2(toGpuU(u.x), toGpuU(u.y))) > 1e-4;
    }
    CHECK(tested > 19000);
    CHECK(far <= tested / 1000);
    CHECK(otherU <= tested / 100);
  }
}

TEST_CASE("env-ot product: chi2 against its own pdf on hard maps (GGX and Lambert), pdf integrating to 1") {
  // The smooth and the sun-with-a-zero-half 64 x 32 maps: the others add time (the harness refines along
  // every edge of the head's cells, slowest under the sanitizers) and cover no other branch.
  std::vector<test::NamedEnv> envs;
  for (auto& env : test::samplerTestEnvs())
    if (env.name == "smooth-64x32" || env.name == "sun-zero-64x32") envs.push_back(std::move(env));
  REQUIRE(envs.size() == 2);
  const auto lobes = testLobes();
  uint64_t seed = 700;
  for (const auto& env : envs) {
    const EnvOtSampler ot(buildEnvOt(env.image));
    const EnvOtInverse inverse = buildEnvOtInverse(ot.data());
    const EnvProductLevel grid = buildEnvOtProductGrid(ot);
    for (const Lobe& lobe : lobes) {
      // envs.size() + 1 runs: the sun-zero map takes the Lambert lobe as well.
      if (lobe.alpha == 0.0 && env.name.rfind("sun-zero", 0) != 0) continue;
      CAPTURE(env.name);
      CAPTURE(lobe.name);
      const EnvOtProductSampler sampler(ot, inverse, grid, lobeAtCells(grid, lobe));
      const test::Chi2Result r = test::runChi2(sampler, "env-ot-product-" + env.name + "-" + lobe.name,
                                               int(envs.size()) + 1, seed++);
      INFO(r.message);
      CHECK(r.passed);
      CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(1e-3));
      // Each sample's pdf (from the cell chosen) is pdf() of its direction (from the preimages located),
      // and a sample never lands on a black texel.
      int differing = 0;
      for (const glm::dvec2 u : test::uniformPoints(5000, seed)) {
        const EnvSample s = sampler.sample(u);
        REQUIRE(s.pdfSolidAngle > 0.0);
        CHECK(env.image.weight(s.texel.x, s.texel.y) > 0.0);
        differing += !(std::abs(s.pdfSolidAngle - sampler.pdf(s.direction)) <= 1e-6 * s.pdfSolidAngle);
      }
      CHECK(differing <= 25);
    }
  }
}

TEST_CASE("env-ot product: a split sun's texels sum the head over both preimages") {
  const EnvImage image = sunAndZeroHalf(64, 32);
  const EnvOtSampler ot(buildEnvOt(image));
  const EnvOtData& d = ot.data();
  REQUIRE(d.rows == d.grid + 1);  // the sun is split: its texels are reached from two places in u
  const EnvOtInverse inverse = buildEnvOtInverse(d);
  const EnvProductLevel grid = buildEnvOtProductGrid(ot);
  const float sunStart = d.rowCdf[std::size_t(d.grid)];
  // The sun's texels: those with a sun-row share.
  std::vector<glm::ivec2> sunTexels;
  for (int y = 0; y < d.height; ++y)
    for (int x = 0; x < d.width; ++x)
      if (inverse.branchPdf[std::size_t(y) * d.width + x].y > 0.0f) sunTexels.emplace_back(x, y);
  REQUIRE(!sunTexels.empty());
  // Two heads that tell the branches apart: all of f cos on the cells over the sun row, or none of it.
  for (const bool onSunRow : {true, false}) {
    CAPTURE(onSunRow);
    std::vector<double> f(grid.nodes());
    for (std::size_t j = 0; j < grid.nodes(); ++j)
      f[j] = (grid.rects[j].w > sunStart) == onSunRow ? 1.0 : 0.0;
    const EnvOtProductSampler sampler(ot, inverse, grid, f);
    // Both preimages map to the direction, in their own branch; the pdf is the sum over them.
    double integral = 0.0, integralMap = 0.0;
    for (const glm::ivec2 texel : sunTexels) {
      const double omega = latLongTexelSolidAngle(texel.y, d.width, d.height);
      constexpr int kSteps = 16;
      for (int b = 0; b < kSteps; ++b)
        for (int a = 0; a < kSteps; ++a) {
          const glm::dvec3 w =
              texelToDirection(texel.x, texel.y, {(a + 0.5) / kSteps, (b + 0.5) / kSteps}, d.width, d.height);
          const EnvOtPreimages pre = envOtPreimages(d, inverse, w);
          REQUIRE(pre.map.has_value());
          REQUIRE(pre.sun.has_value());
          CHECK(pre.map->y < double(sunStart));
          CHECK(pre.sun->y >= double(sunStart));
          CHECK(glm::length(ot.sample(*pre.map).direction - w) < 1e-4);
          CHECK(glm::length(ot.sample(*pre.sun).direction - w) < 1e-4);
          const double expected =
              sampler.headDensity(*pre.map) * pre.mapPdf + sampler.headDensity(*pre.sun) * pre.sunPdf;
          CHECK(sampler.pdf(w) == doctest::Approx(expected).epsilon(1e-12));
          integral += sampler.pdf(w) * omega / (kSteps * kSteps);
          integralMap += sampler.headDensity(*pre.map) * pre.mapPdf * omega / (kSteps * kSteps);
        }
    }
    // The share of samples in the sun's texels is the pdf's integral over them (both branches counted).
    constexpr std::size_t kCount = 200000;
    std::size_t inSun = 0;
    for (const glm::dvec2 u : test::uniformPoints(kCount, onSunRow ? 31 : 32)) {
      const EnvSample s = sampler.sample(u);
      inSun += std::find(sunTexels.begin(), sunTexels.end(), s.texel) != sunTexels.end();
      if (std::find(sunTexels.begin(), sunTexels.end(), s.texel) != sunTexels.end())
        CHECK(s.pdfSolidAngle == doctest::Approx(sampler.pdf(s.direction)).epsilon(1e-6));
    }
    const double share = double(inSun) / kCount;
    const double sigma = std::sqrt(integral * (1.0 - integral) / kCount);
    INFO("sampled share " << share << ", pdf integral " << integral);
    INFO("map branch " << integralMap << ", sun branch " << integral - integralMap);
    CHECK(std::abs(share - integral) < 5.0 * sigma + 1e-3 * integral);
  }
  CHECK_THROWS_AS(EnvOtProductSampler(ot, inverse, grid, std::vector<double>(3, 1.0)), Error);
}

}  // namespace iblx
