// The OT samplers' CPU pdf twins of engine/sampling/env/env_ot_diagnostics.h against the GPU techniques: at
// the directions env-ot-inv and env-ot-fwd sample, and at directions spread over the sphere, the CPU pdf in
// double equals the GPU's in float, so the chi^2 that `iblx otmap --diagnose` reports is the samplers' own.
#include "engine/sampling/env/env_ot_diagnostics.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/support/chi2.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>

using namespace iblx;
using namespace iblx::test;

TEST_CASE("env-ot-inv, env-ot-fwd: the diagnostics' CPU pdfs agree with the GPU techniques") {
  std::vector<NamedEnv> envs = samplerTestEnvs();
  envs.push_back({"sun-split-64x32", sunOverSky(64, 32, 1e4, 2, 20, 9)});  // the mixture with a sun part
  const auto u = uniformPoints(20000, 13);
  // Directions spread over the sphere: uniform in phi and cos(theta).
  std::vector<glm::dvec3> spread;
  for (const glm::dvec2& p : uniformPoints(20000, 17)) {
    const double cosTheta = 1.0 - 2.0 * p.y, sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    spread.push_back({sinTheta * std::cos(2.0 * kPi * p.x), cosTheta, sinTheta * std::sin(2.0 * kPi * p.x)});
  }
  for (const auto& env : envs) {
    const EnvOtSamplerMaps maps = envOtSamplerMaps(env.image);
    if (env.name == "sun-split-64x32") REQUIRE(maps.sun.sunShare > 0.0f);
    for (const bool inverse : {true, false}) {
      const std::string technique = inverse ? "env-ot-inv" : "env-ot-fwd";
      INFO(technique << " on " << env.name);
      const auto cpuPdf = [&](glm::dvec3 w) { return inverse ? envOtInvPdf(maps, w) : envOtFwdPdf(maps, w); };
      EnvTechniqueProbe probe(technique, env.image);
      // A pdf is "the same" within 1e-3: float against double, and a direction within rounding of a piece
      // edge may be located in the neighbouring piece (measured: at most 3 of the 20 000 directions).
      const auto differs = [](double cpu, double gpu) {
        return std::abs(cpu - gpu) > 1e-3 * std::max(cpu, gpu);
      };
      std::size_t sampledDiffering = 0, sampled = 0;
      for (const ProbeSample& s : probe.sample(u)) {
        if (!(s.pdf > 0.0)) continue;
        ++sampled;
        sampledDiffering += differs(cpuPdf(s.direction), s.pdf);
      }
      CHECK(sampled >= u.size() * 99 / 100);
      CHECK(sampledDiffering <= sampled / 1000);
      const std::vector<double> gpuPdf = probe.pdf(spread);
      std::size_t spreadDiffering = 0;
      for (std::size_t i = 0; i < spread.size(); ++i)
        spreadDiffering += differs(cpuPdf(spread[i]), gpuPdf[i]);
      CHECK(spreadDiffering <= spread.size() / 1000);
    }
  }
  checkNoNewValidationErrors();
}
