// Tests of the samplers' offline diagnostics (engine/sampling/env/env_ot_diagnostics.h): chi^2 against
// hand-worked and analytic values, the texel samplers' own pdfs (chi^2 0 up to float rounding), the OT pdf
// twins on an identity map (texel probabilities known in closed form, with and without a sun split off), the
// non-convex share of a grid with one reflex corner, and a solved map's pdfs integrating to 1 with a round
// trip within a cell.
#include "engine/sampling/env/env_ot_diagnostics.h"

#include "engine/core/error.h"
#include "engine/io/synthetic_envs.h"
#include "engine/sampling/env/env_cdf.h"
#include "engine/sampling/env/env_hier.h"
#include "engine/io/latlong_texel.h"
#include "engine/ot/solver.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

using namespace iblx;

namespace {

// An OtMap whose vertices stay where they are: F and G are the identity of the unit square.
OtMap identityMap(int n) {
  OtMap map;
  map.n = n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) map.vertices.push_back(glm::dvec2(double(i) / n, double(j) / n));
  return map;
}

// dOmega / (du dv) in row r of an n-row parameter square: 2 pi n (cos(theta0) - cos(theta1)).
double rowJacobian(int r, int n) {
  return 2.0 * kPi * n * (std::cos(kPi * r / n) - std::cos(kPi * (r + 1) / n));
}

}  // namespace

TEST_CASE("texel chi^2: hand-worked values, unreachable mass and bad input") {
  // p = (1/2, 1/4, 1/4) against the uniform q = 1/3: 3 (1/4 + 1/16 + 1/16) - 1 = 1/8.
  const std::vector<double> p{0.5, 0.25, 0.25};
  const TexelChi2 uniform = texelChi2(p, std::vector<double>{1.0 / 3, 1.0 / 3, 1.0 / 3});
  CHECK(uniform.chi2 == doctest::Approx(0.125).epsilon(1e-12));
  CHECK(uniform.unreachableMass == 0.0);
  CHECK(uniform.qMass == doctest::Approx(1.0));
  // A q off by a common factor (an integration error shared by every texel) is normalised away.
  const TexelChi2 scaled = texelChi2(p, std::vector<double>{0.5 / 3, 0.5 / 3, 0.5 / 3});
  CHECK(scaled.chi2 == doctest::Approx(0.125).epsilon(1e-12));
  CHECK(scaled.qMass == doctest::Approx(0.5));
  // The texel pdf itself: 0. A sampler that never reaches the third texel: its mass is reported apart.
  CHECK(std::abs(texelChi2(p, p).chi2) < 1e-15);
  const TexelChi2 blind = texelChi2(p, std::vector<double>{0.5, 0.5, 0.0});
  CHECK(blind.unreachableMass == doctest::Approx(0.25));
  CHECK(blind.chi2 == doctest::Approx(0.25 / 0.5 + 0.0625 / 0.5 - 1.0));
  CHECK_THROWS_AS(texelChi2(p, std::vector<double>{0.5, 0.5}), Error);
  CHECK_THROWS_AS(texelChi2(p, std::vector<double>{0.5, -0.5, 1.0}), Error);
  CHECK_THROWS_AS(texelChi2(p, std::vector<double>{0.0, 0.0, 0.0}), Error);
}

TEST_CASE("texel chi^2 of a uniform sphere sampler on a sunny sky is the analytic sum p^2 / q - 1") {
  const EnvImage env = sunOverSky(48, 24, 1e3, 2, 10, 6);
  const std::vector<double> p = texelProbabilities(env);
  const std::vector<double> q =
      integrateTexelProbabilities([](glm::dvec3) { return 1.0 / (4.0 * kPi); }, env.width, env.height, 3);
  double analytic = -1.0;
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const double pt = p[std::size_t(y) * env.width + x];
      analytic += pt * pt / (latLongTexelSolidAngle(y, env.width, env.height) / (4.0 * kPi));
    }
  const TexelChi2 result = texelChi2(p, q);
  CHECK(result.qMass == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(result.chi2 == doctest::Approx(analytic).epsilon(1e-10));
  CHECK(result.chi2 > 10.0);  // the sun: far from the texel pdf
}

TEST_CASE("env-cdf and env-hier: chi^2 of the texel pdf against their own pdfs is 0 up to float rounding") {
  std::vector<test::NamedEnv> envs = test::samplerTestEnvs();
  envs.push_back({"sun-1e4", sunOverSky(64, 32, 1e4, 2, 20, 9)});
  for (const auto& env : envs) {
    INFO(env.name);
    const std::vector<double> p = texelProbabilities(env.image);
    const EnvCdfSampler cdf(buildEnvCdf(env.image));
    const EnvHierSampler hier(buildEnvHier(env.image));
    const auto w = env.image.width, h = env.image.height;
    const TexelChi2 cdfChi2 =
        texelChi2(p, integrateTexelProbabilities([&](glm::dvec3 d) { return cdf.pdf(d); }, w, h, 2));
    const TexelChi2 hierChi2 =
        texelChi2(p, integrateTexelProbabilities([&](glm::dvec3 d) { return hier.pdf(d); }, w, h, 2));
    CHECK(std::abs(cdfChi2.chi2) < 1e-6);
    CHECK(std::abs(hierChi2.chi2) < 1e-6);
    CHECK(cdfChi2.unreachableMass == 0.0);
    CHECK(hierChi2.unreachableMass == 0.0);
    CHECK(cdfChi2.qMass == doctest::Approx(1.0).epsilon(1e-5));
    CHECK(hierChi2.qMass == doctest::Approx(1.0).epsilon(1e-5));
  }
}

TEST_CASE("OT parameter square: the two directions invert each other and the rows cover the sphere") {
  const int n = 16;
  double total = 0.0;
  for (int r = 0; r < n; ++r) total += rowJacobian(r, n) / n;
  CHECK(total == doctest::Approx(4.0 * kPi).epsilon(1e-12));
  for (const glm::dvec2 x :
       {glm::dvec2(0.1, 0.02), glm::dvec2(0.7, 0.5), glm::dvec2(0.35, 0.77), glm::dvec2(0.9, 0.999)}) {
    double forwardJacobian = 0.0, backJacobian = 0.0;
    const glm::dvec3 w = otParameterToDirection(x, n, forwardJacobian);
    CHECK(glm::length(w) == doctest::Approx(1.0).epsilon(1e-12));
    const glm::dvec2 back = otDirectionToParameter(w, n, backJacobian);
    CHECK(glm::length(back - x) < 1e-12);
    CHECK(forwardJacobian == doctest::Approx(rowJacobian(int(x.y * n), n)).epsilon(1e-12));
    CHECK(backJacobian == doctest::Approx(forwardJacobian).epsilon(1e-12));
  }
}

TEST_CASE("OT pdf twins on an identity map: texel probabilities in closed form, with and without a sun") {
  // 32 x 16 texels over 8 parameter rows: every texel lies in one row r, where pOt = 1 / J_r exactly, so a
  // texel's OT probability is Omega(y) / J_r; a sun texel adds sunShare times its share of the sun part.
  const int width = 32, height = 16, n = 8;
  const EnvImage env = sunOverSky(width, height, 1e5, 1, 11, 5);
  const std::vector<double> weights = texelSamplingWeights(env, "test");
  for (const double clip : {0.0, kOtSunClip}) {
    INFO("sun clip " << clip);
    const EnvOtSamplerMaps maps = envOtSamplerMaps(splitOtSun(weights, width, height, clip), identityMap(n));
    CHECK((clip > 0.0) == (maps.sun.sunShare > 0.0f));
    const double share = double(maps.sun.sunShare);
    for (const bool inverse : {false, true}) {
      const std::vector<double> q = integrateTexelProbabilities(
          [&](glm::dvec3 w) { return inverse ? envOtInvPdf(maps, w) : envOtFwdPdf(maps, w); }, width, height,
          4);
      double mass = 0.0, worst = 0.0;
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          const double expected =
              share * double(maps.sun.texelProbability(x, y)) +
              (1.0 - share) * latLongTexelSolidAngle(y, width, height) / rowJacobian(y * n / height, n);
          const double got = q[std::size_t(y) * width + x];
          worst = std::max(worst, std::abs(got - expected) / expected);
          mass += got;
        }
      CHECK(worst < 1e-9);
      CHECK(mass == doctest::Approx(1.0).epsilon(1e-9));
    }
    CHECK(nonConvexShare(maps.forward) == 0.0);
    CHECK(nonConvexShare(maps.inverse) == 0.0);
    CHECK(inverseRoundTrip(maps.forward, maps.inverse, 64).max < 1e-12);
    CHECK(forwardRoundTrip(maps.forward, 64).max < 1e-12);
  }
}

TEST_CASE("nonConvexShare: one reflex corner makes one of 16 quads a split piece") {
  // Vertex (2, 2) of a 4 x 4 grid moved from (0.5, 0.5) to (0.7, 0.7): cell (2, 2) gets a reflex corner
  // there; the three other cells around it stay convex (worked out by hand with the corner cross products).
  std::vector<glm::dvec2> vertices;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) vertices.push_back(glm::dvec2(i / 4.0, j / 4.0));
  vertices[2 * 5 + 2] = glm::dvec2(0.7, 0.7);
  const QuadGridMap map(4, vertices);
  CHECK(map.pieces()[2 * 4 + 2] != QuadPiece::Bilinear);
  CHECK(nonConvexShare(map) == doctest::Approx(1.0 / 16.0));
}

TEST_CASE("OT pdf twins on a solved sunny map: both integrate to 1, the inverse round trip stays in a cell") {
  const int width = 64, height = 32, n = 32;
  const EnvImage env = sunOverSky(width, height, 1e4, 2, 20, 9);
  OtSunSplit sun = splitOtSun(texelSamplingWeights(env, "test"), width, height);
  REQUIRE(sun.sunShare > 0.0f);
  const OtMap map = solveOtMap(otDensityFromWeights(sun.smoothWeights, width, height, n), n);
  const EnvOtSamplerMaps maps = envOtSamplerMaps(std::move(sun), map);
  const std::vector<double> p = texelProbabilities(env);
  const TexelChi2 fwd = texelChi2(
      p, integrateTexelProbabilities([&](glm::dvec3 w) { return envOtFwdPdf(maps, w); }, width, height, 8));
  const TexelChi2 inv = texelChi2(
      p, integrateTexelProbabilities([&](glm::dvec3 w) { return envOtInvPdf(maps, w); }, width, height, 8));
  CHECK(fwd.qMass == doctest::Approx(1.0).epsilon(2e-3));
  CHECK(inv.qMass == doctest::Approx(1.0).epsilon(2e-3));
  CHECK(fwd.unreachableMass == 0.0);
  CHECK(inv.unreachableMass == 0.0);
  // The density floor and the grid coarser than the texels: above 0, but the suns split off keep it small.
  CHECK(fwd.chi2 > 1e-4);
  CHECK(fwd.chi2 < 1.0);
  // G tabulates F's inverse: the two pdfs differ only by the bilinear interpolation between G's vertices.
  CHECK(inv.chi2 == doctest::Approx(fwd.chi2).epsilon(0.2));
  const MapRoundTrip inverseTrip = inverseRoundTrip(maps.forward, maps.inverse, 128);
  CHECK(inverseTrip.max > 0.0);
  CHECK(inverseTrip.max < 1.0 / n);
  CHECK(inverseTrip.mean < inverseTrip.max);
  const MapRoundTrip forwardTrip = forwardRoundTrip(maps.forward, 128);
  CHECK(forwardTrip.missed == 0);
  CHECK(forwardTrip.max < 1e-9);
}
