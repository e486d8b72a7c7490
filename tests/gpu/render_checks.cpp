// Helpers shared by the end-to-end GPU tests (tests/gpu/render_checks.h).
#include "tests/gpu/render_checks.h"

#include "engine/render/reference.h"
#include "tests/gpu/gpu_fixture.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

namespace iblx::test {

std::vector<MethodSpec> allMethodSpecs(const BrdfInfo& brdf, const std::string& sequence) {
  std::vector<MethodSpec> specs;
  for (const auto& m : methodRegistry()) {
    MethodSpec spec;
    spec.method = m.name;
    spec.sequence = sequence;
    // By the strategy's capabilities: each technique the method lets the user choose is covered.
    const StrategyInfo& s = m.strategyInfo();
    if (!s.envTechniqueChosen && !(s.usesBrdfTechnique && !s.usesEnvTechnique)) {
      // The env technique is the method's own; product-mis takes the BRDF's best sampler, as MIS below
      // already pairs every BRDF technique with the env techniques.
      specs.push_back(spec);
    } else if (!s.usesEnvTechnique) {
      for (const auto& t : brdfTechniqueRegistry())
        if (t.appliesTo(brdf)) specs.push_back((spec.brdfSampler = t.name, spec));
    } else if (!s.usesBrdfTechnique) {
      for (const auto& e : envTechniqueRegistry()) specs.push_back((spec.envSampler = e.name, spec));
    } else {
      // Every env technique with every BRDF technique that applies (balance), and with the BRDF's best
      // sampler also under the power heuristic.
      // The optimal-transport techniques pair with the BRDF's best sampler only: MIS combines any env part
      // with any BRDF part by the same code, every BRDF technique is paired with env-cdf and env-hier, and
      // the three OT parts' pipelines made every combination take about a minute more on lavapipe.
      for (const auto& e : envTechniqueRegistry())
        for (const auto& t : brdfTechniqueRegistry()) {
          if (!t.appliesTo(brdf)) continue;
          if (e.name.rfind("env-ot", 0) == 0 && t.name != brdf.bestSampler) continue;
          spec.envSampler = e.name;
          spec.brdfSampler = t.name;
          spec.misHeuristic = "balance";
          specs.push_back(spec);
          if (t.name == brdf.bestSampler) {
            if (s.misWeights) specs.push_back((spec.misHeuristic = "power", spec));
            if (s.misSplit &&
                (e.name == "env-cdf" || e.name == "env-hier")) {  // the table-based ones, compensated
              MethodSpec compensated = spec;
              compensated.misHeuristic = "balance";
              compensated.misCompensation = true;
              specs.push_back(compensated);
            }
            if (s.misSplit && e.name == "env-cdf") {  // one-sample MIS with an uneven split
              MethodSpec oneSample = spec;
              oneSample.misHeuristic = "balance";
              oneSample.misEnvFraction = 0.3;
              specs.push_back(oneSample);
            }
          }
        }
    }
  }
  return specs;
}

glm::dvec3 hemisphere(glm::dvec2 u) {
  const double z = u.x, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * 3.14159265358979323846 * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}

glm::dvec3 viewAt(double thetaDegrees, double phiDegrees) {
  const double t = thetaDegrees * 3.14159265358979323846 / 180.0,
               p = phiDegrees * 3.14159265358979323846 / 180.0;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

Scene sceneWith(EnvImage env, const std::string& brdf,
                std::vector<std::pair<std::string, std::string>> params, int size, const std::string& object,
                const CameraSpec& camera) {
  SceneSpec spec;
  spec.brdf = brdf;
  spec.params = std::move(params);
  spec.width = spec.height = size;
  spec.object = object;
  spec.camera = camera;
  return makeScene(std::move(env), spec);
}

MeanErrorZTest zTest(const Scene& scene, const Renderer& renderer, const std::vector<float>& reference) {
  return zTestMeanError(scene.gbuffer, renderer.meanRgb(), renderer.varianceRgb(),
                        double(renderer.samplesPerPixel()), reference);
}

void checkFiniteForEveryMethod(const Scene& scene, const std::string& name, uint32_t seed) {
  for (const char* sequence : {"random", "sobol"})
    for (const auto& spec : allMethodSpecs(*scene.brdf, sequence)) {
      const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
      INFO(name << ": " << method.label());
      Renderer renderer(gpuContext(), gpuCompiler(), scene, method, seed);
      renderer.runPass(32);
      CHECK(renderer.nonFiniteSamples() == 0);
      int bad = 0;
      for (float v : renderer.meanRgb()) bad += !std::isfinite(v) || v < 0.0f;
      CHECK(bad == 0);
    }
}

std::vector<MethodSpec> methodSpecs(const BrdfInfo& brdf, MethodSet set) {
  std::vector<MethodSpec> specs;
  if (set == MethodSet::EveryMethod) {
    for (MethodSpec spec : defaultMethodSpecs(brdf)) specs.push_back((spec.sequence = "sobol", spec));
    return specs;
  }
  for (const char* sequence : {"random", "sobol"})
    for (const MethodSpec& spec : allMethodSpecs(brdf, sequence)) specs.push_back(spec);
  return specs;
}

void checkWhiteFurnace(const Scene& scene, double albedo, int passes, double sigmas, MethodSet set) {
  for (const auto& spec : methodSpecs(*scene.brdf, set)) {
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(method.label());
    Renderer renderer(gpuContext(), gpuCompiler(), scene, method, 3);
    for (int pass = 0; pass < passes; ++pass) renderer.runPass(64);
    const auto mean = renderer.meanRgb();
    const auto var = renderer.varianceRgb();
    const double n = double(renderer.samplesPerPixel());
    // A pixel's own variance estimate is low exactly when its mean is high for weights with a point mass at
    // 0 (samples that reflect below the horizon, as with brdf-tab): the mean and variance estimates are
    // correlated. So the bound uses the larger of the pixel's variance and the median over the object.
    std::vector<double> variances;
    for (size_t i = 0; i < scene.gbuffer.pixels.size(); ++i)
      if (scene.gbuffer.pixels[i].normal.w != 0.0f) variances.push_back(var[3 * i]);
    std::nth_element(variances.begin(), variances.begin() + std::ptrdiff_t(variances.size() / 2),
                     variances.end());
    const double medianVariance = variances[variances.size() / 2];
    int failures = 0;
    for (size_t i = 0; i < scene.gbuffer.pixels.size(); ++i) {
      if (scene.gbuffer.pixels[i].normal.w == 0.0f) continue;
      const double bound = sigmas * std::sqrt(std::max(double(var[3 * i]), medianVariance) / n) + 1e-4;
      if (std::abs(mean[3 * i] - albedo) > bound) {
        ++failures;
        MESSAGE(method.label() << ": pixel " << i << " mean " << mean[3 * i] << ", bound " << bound);
      }
    }
    CHECK(failures == 0);
    CHECK(renderer.nonFiniteSamples() == 0);
  }
  checkNoNewValidationErrors();
}

void checkChi2AgainstPdf(BrdfTechniqueProbe& probe, std::span<const glm::dvec3> directions, int testCount,
                         const std::string& label) {
  Chi2Options options;
  options.testCount = testCount;
  options.label = label;
  options.ires = 12;
  const Chi2Result r = chi2Test(
      directions, [&](std::span<const glm::dvec3> d) { return probe.pdf(d); }, options);
  INFO(r.message);
  CHECK(r.passed);
  CHECK(r.pdfIntegral == doctest::Approx(1.0).epsilon(5e-3));
}

void checkConvergesToReference(const Scene& scene, const std::string& name, double zBound, MethodSet set) {
  const ReferenceImage ref = computeReference(gpuContext(), gpuCompiler(), scene);
  for (const auto& spec : methodSpecs(*scene.brdf, set)) {
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(name << ": " << method.label());
    Renderer renderer(gpuContext(), gpuCompiler(), scene, method, 17);
    for (int pass = 0; pass < 8; ++pass) renderer.runPass(64);
    const MeanErrorZTest t = zTest(scene, renderer, ref.rgb);
    for (int ch = 0; ch < 3; ++ch) {
      INFO("channel " << ch << ": mean error " << t.meanError[ch] << ", standard error "
                      << t.standardError[ch]);
      CHECK(std::abs(t.z[ch]) < zBound);
    }
    CHECK(renderer.nonFiniteSamples() == 0);
  }
  checkNoNewValidationErrors();
}

ReferenceComparison compareReferences(const Scene& a, const Scene& b) {
  const ReferenceImage ra = computeReference(gpuContext(), gpuCompiler(), a);
  const ReferenceImage rb = computeReference(gpuContext(), gpuCompiler(), b);
  double sumA = 0.0, sumB = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < a.gbuffer.pixels.size(); ++i) {
    if (a.gbuffer.pixels[i].normal.w == 0.0f) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      sumA += ra.rgb[3 * i + c];
      sumB += rb.rgb[3 * i + c];
      worst = std::max(worst, std::abs(rb.rgb[3 * i + c] - ra.rgb[3 * i + c]) / (ra.rgb[3 * i + c] + 1e-2));
    }
  }
  return {sumB / sumA, worst};
}

}  // namespace iblx::test
