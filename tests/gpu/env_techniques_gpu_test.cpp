// Every env technique of the registry, on the GPU: pdf integrates to 1, chi-square of the sample histogram
// against the pdf on smooth and hard maps, sample()'s pdf agrees with pdf(), and the table-based techniques
// agree with their CPU twins on the same u.
#include "engine/scene/methods.h"
#include "engine/sampling/env/env_cdf.h"
#include "engine/sampling/env/env_hier.h"
#include "engine/sampling/env/env_ot.h"
#include "engine/sampling/product/env_ot_product.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/support/chi2.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace iblx;
using namespace iblx::test;

namespace {

constexpr std::size_t kSamples = 200000;

void checkTechniqueOnEnv(const std::string& technique, const NamedEnv& env, int testCount) {
  INFO("technique " << technique << " on " << env.name);
  const glm::dvec3 normal = glm::normalize(glm::dvec3(0.3, 0.8, 0.5));
  EnvTechniqueProbe probe(technique, env.image, normal);
  const auto u = uniformPoints(kSamples, 7);
  const auto samples = probe.sample(u);
  std::vector<glm::dvec3> directions;
  std::size_t mismatches = 0;
  for (const auto& s : samples) {
    REQUIRE(std::isfinite(s.pdf));
    REQUIRE(std::isfinite(s.direction.x));
    if (!(s.pdf > 0.0)) continue;  // a zero-pdf sample contributes nothing and is not part of the histogram
    directions.push_back(s.direction);
    // The pdf returned with a sample is the pdf() of that direction, except within float rounding of a texel
    // edge.
    if (std::abs(s.pdf - s.pdfLookup) > 1e-4 * s.pdf) ++mismatches;
  }
  // env-ot-inv's pdf() inverts its map in float by point location; in the slivers next to a sun or a zero
  // region the located piece can differ from the sampled one within rounding (measured: 0.03%).
  const bool locatesPreimage = technique == "env-ot-inv";
  CHECK(mismatches <= kSamples / (locatesPreimage ? 1000 : 10000));
  CHECK(directions.size() >= kSamples * 99 / 100);
  Chi2Options options;
  options.testCount = testCount;
  options.label = technique + "-" + env.name;
  // The OT maps' pdfs vary inside a chi-square cell (bilinear pieces, peaks where the map compresses near the
  // poles); the 4 x 4 midpoint rule misses 1% of env-ot-inv's integral there, 16 x 16 integrates it to 1e-4.
  if (technique.rfind("env-ot-", 0) == 0) options.ires = 16;
  const Chi2Result result = chi2Test(
      directions, [&](std::span<const glm::dvec3> d) { return probe.pdf(d); }, options);
  INFO(result.message);
  CHECK(result.passed);
  CHECK(result.pdfIntegral == doctest::Approx(1.0).epsilon(2e-3));
}

}  // namespace

TEST_CASE("env techniques: pdf integrates to 1 and chi2 passes on smooth and hard maps") {
  const auto envs = samplerTestEnvs();
  const int testCount = int(envTechniqueRegistry().size() * envs.size());
  for (const auto& technique : envTechniqueRegistry())
    for (const auto& env : envs) {
      SUBCASE((technique.name + " " + env.name).c_str()) {
        checkTechniqueOnEnv(technique.name, env, testCount);
      }
    }
  checkNoNewValidationErrors();
}

template <typename CpuSampler, typename Build>
void checkAgainstCpuTwin(const std::string& technique, Build build) {
  for (const auto& env : samplerTestEnvs()) {
    INFO(technique << " on " << env.name);
    const CpuSampler cpu(build(env.image));
    EnvTechniqueProbe probe(technique, env.image);
    const auto u = uniformPoints(20000, 11);
    const auto gpuSamples = probe.sample(u);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < u.size(); ++i) {
      const EnvSample c = cpu.sample(u[i]);
      const ProbeSample& g = gpuSamples[i];
      const bool sameDirection = glm::length(c.direction - g.direction) < 1e-4;
      const bool samePdf = std::abs(c.pdfSolidAngle - g.pdf) <= 1e-4 * c.pdfSolidAngle;
      differing += !(sameDirection && samePdf);
    }
    // Identical float arithmetic except transcendental rounding near texel edges.
    CHECK(differing <= u.size() / 1000);
  }
}

TEST_CASE("env-cdf: GPU agrees with the CPU twin") {
  checkAgainstCpuTwin<EnvCdfSampler>("env-cdf", [](const EnvImage& e) { return buildEnvCdf(e); });
  checkNoNewValidationErrors();
}

TEST_CASE("env-hier: GPU agrees with the CPU twin") {
  checkAgainstCpuTwin<EnvHierSampler>("env-hier", [](const EnvImage& e) { return buildEnvHier(e); });
  checkNoNewValidationErrors();
}

TEST_CASE("env-ot: GPU agrees with the CPU twin") {
  checkAgainstCpuTwin<EnvOtSampler>("env-ot", [](const EnvImage& e) { return buildEnvOt(e); });
  checkNoNewValidationErrors();
}

TEST_CASE("env-ot inverse (product-warp-ot): GPU agrees with the CPU twin, both branches") {
  for (const auto& env : samplerTestEnvs()) {
    INFO("env-ot inverse on " << env.name);
    const EnvOtData data = buildEnvOt(env.image);
    const EnvOtSampler ot(data);
    const EnvOtInverse inverse = buildEnvOtInverse(data);
    EnvPartProbe probe("probe/env_ot_inverse_probe.comp",
                       {findEnvTechnique("env-ot").part, "lib/env_ot_inverse.glsl"},
                       envOtProductTechniqueData(data), env.image);
    // Directions env-ot samples (the sun's texels among them where it is split).
    std::vector<glm::dvec3> directions;
    for (const glm::dvec2 u : uniformPoints(10000, 13)) {
      const EnvSample s = ot.sample(u);
      if (s.pdfSolidAngle > 0.0) directions.push_back(s.direction);
    }
    const auto gpu = probe.directions(directions);
    std::size_t differing = 0, sunTexels = 0;
    for (std::size_t i = 0; i < directions.size(); ++i) {
      const EnvOtPreimages cpu = envOtPreimages(data, inverse, directions[i]);
      const auto& [map, sun] = gpu[i];
      const auto same = [](const std::optional<glm::dvec2>& c, const glm::dvec4& g) {
        return c.has_value() == (g.z > 0.5) && (!c || glm::length(*c - glm::dvec2(g)) < 1e-4);
      };
      const bool samePdfs = std::abs(map.w - cpu.mapPdf) <= 1e-6 * cpu.mapPdf &&
                            std::abs(sun.w - cpu.sunPdf) <= 1e-6 * cpu.sunPdf;
      sunTexels += cpu.sun.has_value();
      differing += !(same(cpu.map, map) && same(cpu.sun, sun) && samePdfs);
    }
    INFO(sunTexels << " directions in sun texels");
    if (data.rows > data.grid) CHECK(sunTexels > 0);
    // Float barycentrics on the GPU: a direction on a piece's edge may be placed in the neighbour.
    CHECK(differing <= directions.size() / 200);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("env-cdf, env-hier: zero-weight texels are never sampled") {
  const EnvImage env = sunAndZeroHalf(64, 32);
  for (const char* technique : {"env-cdf", "env-hier"}) {
    EnvTechniqueProbe probe(technique, env);
    const auto samples = probe.sample(uniformPoints(100000, 3));
    std::size_t inZero = 0;
    for (const auto& s : samples) inZero += s.direction.y < -1e-6;  // the lower half is exactly zero
    CHECK_MESSAGE(inZero == 0, technique);
  }
  checkNoNewValidationErrors();
}
