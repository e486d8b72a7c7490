// The hard-case suite at test size: for every case, every method the registry offers by default, with both
// sequences, gives finite output and converges to the reference; plus the measuring loop, the method words of
// `converge --method` and the reference cache.
#include "engine/core/error.h"
#include "engine/render/convergence_runner.h"
#include "engine/render/hard_cases.h"
#include "engine/render/mc_reference.h"
#include "engine/render/metrics.h"
#include "engine/render/reference.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>

namespace iblx::test {
namespace {

std::vector<ResolvedMethod> defaultMethods(const Scene& scene) {
  std::vector<ResolvedMethod> methods;
  for (const char* sequence : {"random", "sobol"})
    for (MethodSpec spec : defaultMethodSpecs(*scene.brdf)) {
      spec.sequence = sequence;
      methods.push_back(resolveMethod(spec, *scene.brdf));
    }
  return methods;
}

// Runs the suite's check on one case: finite images, no NaN/Inf estimate, |z| under the family bound.
// Returns the methods skipped for the device's limits.
std::vector<SkippedMethod> checkHardCase(const HardCase& hardCase, std::span<const ResolvedMethod> methods,
                                         std::uint64_t spp) {
  const Scene scene = makeHardCaseScene(hardCase, HardCaseSize::Test);
  const std::vector<float> reference = hardCase.exactReference
                                           ? hardCase.exactReference(scene)
                                           : computeReference(gpuContext(), gpuCompiler(), scene).rgb;
  ConvergenceBudget budget;
  budget.firstSpp = spp / 4;
  budget.maxSpp = spp;
  budget.pointsPerOctave = 1;
  const std::uint32_t seeds[] = {29};
  const ConvergenceResult result =
      runConvergence(gpuContext(), gpuCompiler(), scene, reference, methods, seeds, budget);
  REQUIRE(result.runs.size() + result.skipped.size() == methods.size());
  // Family of 3 channels x (cases x methods) over the whole suite, about 400 tests: 1e-4 family rate.
  const double zBound = familyZBound(1e-4, 400);
  for (const auto& run : result.runs) {
    INFO(hardCase.name << ": " << run.method << "/" << run.sequence);
    CHECK(run.points.size() == 3);
    CHECK(run.points.back().spp == spp);
    CHECK(run.finiteImage);
    CHECK(run.nonFiniteSamples == 0);
    if (hardCase.zTested) CHECK(run.finalMaxAbsZ < zBound);
  }
  checkNoNewValidationErrors();
  return result.skipped;
}

}  // namespace

TEST_CASE("hard-case suite: every case, every default method, finite and converging (z-test)") {
  for (const auto& hardCase : hardCases()) {
    if (hardCase.name == "huge-map") continue;  // its own test case below, with fewer methods
    const Scene scene = makeHardCaseScene(hardCase, HardCaseSize::Test);
    CHECK(checkHardCase(hardCase, defaultMethods(scene), 512).empty());
  }
}

TEST_CASE("hard case huge-map: more than 2^24 texels, closed-form reference") {
  const HardCase& huge = findHardCase("huge-map");
  const Scene scene = makeHardCaseScene(huge, HardCaseSize::Test);
  CHECK(std::size_t(scene.env.width) * scene.env.height > (std::size_t(1) << 24));
  // The table-based env techniques (their indices run past 2^24), MIS and RIS: four estimators that agree
  // with the closed form.
  std::vector<ResolvedMethod> methods;
  CHECK(huge.excludedMethods == std::vector<std::string>{"uniform", "cosine", "brdf"});
  for (const char* name : {"env-cdf", "env-hier", "mis", "ris"})
    methods.push_back(resolveMethod({name}, *scene.brdf));
  // Its radiance (216 MiB) is uploaded in chunks when one storage buffer cannot hold it; env-hier's shares
  // (16 B for each of the (8192^2 - 1) / 3 interior nodes of its padded pyramid, 341 MiB) must fit one
  // buffer, so a device with less (lavapipe: 128 MiB) skips env-hier with the reason.
  const auto skipped = checkHardCase(huge, methods, 256);
  const std::size_t hierShareBytes = 16 * ((std::size_t(8192) * 8192 - 1) / 3);
  const bool hierFits = gpuContext().limits().maxStorageBufferRange >= hierShareBytes;
  REQUIRE(skipped.size() == (hierFits ? 0u : 1u));
  if (!skipped.empty()) {
    CHECK(skipped[0].method == "env-hier");
    CHECK(skipped[0].reason.find("largest storage buffer") != std::string::npos);
  }
}

TEST_CASE("hard cases: the bad-texels case goes through the loader's sanitation") {
  const Scene scene = makeHardCaseScene(findHardCase("bad-texels"), HardCaseSize::Test);
  for (float v : scene.env.rgb) {
    REQUIRE(std::isfinite(v));
    REQUIRE(v >= 0.0f);
  }
  CHECK_THROWS_WITH_AS(findHardCase("nope"), doctest::Contains("valid: sun-1e3"), Error);
}

TEST_CASE("the reference cache: a second request reads the stored image; another scene misses") {
  const auto dir = std::filesystem::temp_directory_path() / ("iblx-refcache-" + std::to_string(::getpid()));
  const Scene scene = sceneWith(smoothSky(32, 16), "ggx", {{"roughness", "0.3"}}, 16);
  bool fromCache = true;
  const ReferenceImage first = cachedReference(gpuContext(), gpuCompiler(), scene, dir, {}, &fromCache);
  CHECK_FALSE(fromCache);
  const ReferenceImage second = cachedReference(gpuContext(), gpuCompiler(), scene, dir, {}, &fromCache);
  CHECK(fromCache);
  CHECK(second.rgb == first.rgb);  // EXR float: lossless
  const Scene other = sceneWith(smoothSky(32, 16), "ggx", {{"roughness", "0.31"}}, 16);
  CHECK(referenceKey(other) != referenceKey(scene));
  cachedReference(gpuContext(), gpuCompiler(), other, dir, {}, &fromCache);
  CHECK_FALSE(fromCache);
  std::filesystem::remove_all(dir);
}

TEST_CASE(
    "the Monte Carlo reference: its noise estimate is its error against the exact one; cached per half") {
  const auto dir = std::filesystem::temp_directory_path() / ("iblx-mcref-" + std::to_string(::getpid()));
  const Scene scene = sceneWith(sunOverSky(32, 16, 1e3, 2, 10, 4), "ggx", {{"roughness", "0.3"}}, 16);
  const ReferenceImage exact = computeReference(gpuContext(), gpuCompiler(), scene);
  McReferenceOptions options;
  options.seconds = 0.6;
  bool fromCache = true;
  const ReferenceImage mc = cachedMcReference(gpuContext(), gpuCompiler(), scene, dir, options, &fromCache);
  CHECK_FALSE(fromCache);
  // Unbiased: its squared error against the truth is, on average, the noise it reports. Over ~200 object
  // pixels x 3 channels the ratio of the two scatters by well under 2x (seeds fixed: this run is repeatable).
  const ErrorMetrics error = compareToReference(scene.gbuffer, mc.rgb, exact.rgb);
  INFO("MSE against the exact reference " << error.mse << ", estimated noise " << mc.noise.mse);
  CHECK(mc.noise.mse > 0.0);
  CHECK(error.mse > 0.3 * mc.noise.mse);
  CHECK(error.mse < 3.0 * mc.noise.mse);
  // The mean signed error: the noise's own scale over the pixels, plus the exact reference's quadrature error
  // (its own small bias), so a loose 10 sigma (measured: 4-5 sigma in runs of 0.6 s).
  CHECK(std::abs(error.meanSignedError) < 10.0 * std::sqrt(mc.noise.mse / double(3 * error.pixels)) + 1e-6);
  // The second request reads both halves from the cache: the same image and noise.
  const ReferenceImage again =
      cachedMcReference(gpuContext(), gpuCompiler(), scene, dir, options, &fromCache);
  CHECK(fromCache);
  CHECK(again.rgb == mc.rgb);
  CHECK(again.noise.mse == mc.noise.mse);
  std::filesystem::remove_all(dir);
}

TEST_CASE("referenceNoise: (A - B)^2 / 4 over object pixels, relative to (M^2 + 0.01)") {
  GBuffer g;
  g.width = 2, g.height = 1;
  g.pixels.resize(2);
  g.pixels[0].normal.w = 1.0f;  // object
  g.pixels[1].normal.w = 0.0f;  // background: left out
  const std::vector<float> a = {1.0f, 2.0f, 3.0f, 100.0f, 100.0f, 100.0f};
  const std::vector<float> b = {1.2f, 2.0f, 2.6f, 0.0f, 0.0f, 0.0f};
  const ReferenceNoise n = referenceNoise(g, a, b);
  // Channel differences 0.2, 0, 0.4: (0.04 + 0 + 0.16) / 4 / 3.
  CHECK(n.mse == doctest::Approx(0.2 / 12.0).epsilon(1e-6));
  CHECK(n.relMse == doctest::Approx((0.01 / (1.21 + 0.01) + 0.04 / (7.84 + 0.01)) / 3.0).epsilon(1e-6));
}

TEST_CASE("runConvergence: error falls like 1/N on the schedule; Ctrl-C keeps what was measured") {
  const Scene scene = sceneWith(smoothSky(32, 16), "lambert", {}, 16);
  const ReferenceImage ref = computeReference(gpuContext(), gpuCompiler(), scene);
  // i.i.d. samples (`random`): the slope of -1 is theirs; `sobol`'s is steeper.
  const ResolvedMethod methods[] = {resolveMethod({"env-cdf", "", "", "random"}, *scene.brdf)};
  const std::uint32_t seeds[] = {1, 2, 3};
  ConvergenceBudget budget;
  budget.firstSpp = 8;
  budget.maxSpp = 2048;
  budget.pointsPerOctave = 2;
  const ConvergenceResult r =
      runConvergence(gpuContext(), gpuCompiler(), scene, ref.rgb, methods, seeds, budget);
  REQUIRE(r.runs.size() == 3);
  REQUIRE(r.images.size() == 1);
  const ConvergenceSummary s = summarize(r.runs, 1e-4);
  // 8 doublings of spp: the fitted slope of MSE is -1 within the noise of 3 seeds.
  CHECK(s.rows[0].slopeSpp == doctest::Approx(-1.0).epsilon(0.15));
  CHECK(s.rows[0].spp == 2048);
  for (std::size_t i = 1; i < r.runs[0].points.size(); ++i)
    CHECK(r.runs[0].points[i].wallSeconds > r.runs[0].points[i - 1].wallSeconds);

  std::atomic<bool> stop{false};
  int calls = 0;
  const ConvergenceResult partial = runConvergence(
      gpuContext(), gpuCompiler(), scene, ref.rgb, methods, seeds, budget,
      [&](const ConvergenceProgress&) {
        if (++calls == 3) stop = true;
      },
      &stop);
  CHECK(partial.interrupted);
  REQUIRE(partial.runs.size() == 1);
  CHECK(partial.runs[0].points.size() == 3);
}

}  // namespace iblx::test
