// End-to-end tests of the integrator and the reference on lavapipe at small sizes: white furnace,
// unbiasedness (z-test of the mean signed error with the measured variance), 1/N convergence, and no NaN/Inf
// on hard cases.
#include "engine/render/metrics.h"
#include "engine/render/reference.h"
#include "engine/core/error.h"
#include "engine/render/kernel_assembly.h"
#include "engine/render/renderer.h"
#include "engine/sampling/env/env_cdf.h"
#include "engine/scene/brdf_params.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <set>
#include <filesystem>
#include <unistd.h>

using namespace iblx;
using namespace iblx::test;

TEST_CASE("the GPU suite reaches every registry method and technique (allMethodSpecs)") {
  // Every method, every env technique and every BRDF technique that applies to a built-in BRDF is rendered
  // by the tests that iterate allMethodSpecs; a registry entry they do not reach is untested on the GPU.
  std::set<std::string> methods, envTechniques, brdfTechniques;
  for (const BrdfInfo& brdf : brdfRegistry())
    for (const MethodSpec& spec : allMethodSpecs(brdf, "random")) {
      const ResolvedMethod r = resolveMethod(spec, brdf);
      methods.insert(r.method->name);
      if (r.envTechnique) envTechniques.insert(r.envTechnique->name);
      if (r.brdfTechnique) brdfTechniques.insert(r.brdfTechnique->name);
    }
  for (const MethodInfo& m : methodRegistry()) CHECK_MESSAGE(methods.count(m.name), m.name);
  for (const EnvTechniqueInfo& t : envTechniqueRegistry()) CHECK_MESSAGE(envTechniques.count(t.name), t.name);
  for (const BrdfTechniqueInfo& t : brdfTechniqueRegistry()) {
    const bool appliesToBuiltIn = std::any_of(brdfRegistry().begin(), brdfRegistry().end(),
                                              [&](const BrdfInfo& b) { return t.appliesTo(b); });
    if (appliesToBuiltIn) CHECK_MESSAGE(brdfTechniques.count(t.name), t.name);
  }
}

TEST_CASE("white furnace: constant environment 1 and Lambert albedo give the albedo, for every method") {
  // 5 sigma per pixel (about 3e-7 false alarms each).
  checkWhiteFurnace(sceneWith(constantEnv(16, 8, 1.0f), "lambert", {{"albedo", "0.7"}}, 32), 0.7, 4, 5.0);
}

TEST_CASE("reference: white furnace convolution gives the albedo") {
  const Scene scene = sceneWith(constantEnv(32, 16, 1.0f), "lambert", {{"albedo", "0.5,0.6,0.7"}}, 32);
  const ReferenceImage ref = computeReference(gpuContext(), gpuCompiler(), scene);
  double worst = 0;
  for (size_t i = 0; i < scene.gbuffer.pixels.size(); ++i)
    if (scene.gbuffer.pixels[i].normal.w != 0.0f)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(ref.rgb[3 * i + c] - (0.5 + 0.1 * c)));
  CHECK(worst < 2e-4);
  checkNoNewValidationErrors();
}

TEST_CASE("reference: the midpoint rule on fine maps agrees with the Gauss rule") {
  // 256x128 texels are small against the cosine and an alpha = 0.3 lobe, so the reference takes the midpoint
  // rule there; it must agree with 2x2 Gauss points everywhere to well below Monte Carlo noise.
  // Regression: lavapipe ends loops after about 65535 iterations per invocation, which silently truncated the
  // texel loop on maps of this size until dispatches were split by texel count.
  const Scene scene = sceneWith(smoothSky(256, 128), "ggx", {{"roughness", "0.3"}, {"metallic", "0.5"}}, 16);
  ReferenceOptions gauss;
  gauss.allowMidpoint = false;
  const ReferenceImage midpoint = computeReference(gpuContext(), gpuCompiler(), scene);
  const ReferenceImage exact = computeReference(gpuContext(), gpuCompiler(), scene, gauss);
  double worst = 0.0;
  size_t worstIndex = 0;
  for (size_t i = 0; i < midpoint.rgb.size(); ++i) {
    const double d = std::abs(midpoint.rgb[i] - exact.rgb[i]) / (std::abs(exact.rgb[i]) + 1e-3);
    if (d > worst) worst = d, worstIndex = i;
  }
  INFO("worst relative difference " << worst << " at pixel " << worstIndex / 3 << ": "
                                    << midpoint.rgb[worstIndex] << " vs " << exact.rgb[worstIndex]);
  CHECK(worst < 1e-3);
  checkNoNewValidationErrors();
}

TEST_CASE("reference: visiting only each row's interval above the horizon changes no bit") {
  // The sphere sees every direction from some pixel, the plane (at 80 degrees) half of them; rows near the
  // poles, texels at the interval's wrap-around and a rotated map are all crossed. GGX with a sun: fine
  // quadrature zones, bright texels and the horizon band all take part.
  for (const char* object : {"sphere", "plane"}) {
    CAPTURE(object);
    SceneSpec spec;
    spec.width = spec.height = 24;
    spec.object = object;
    spec.camera.elevationDeg = std::string(object) == "plane" ? 80.0 : 20.0;
    spec.envRotationDeg = 37.0;
    spec.brdf = "ggx";
    spec.params = {{"roughness", "0.15"}};
    const Scene scene = makeScene(sunOverSky(96, 48, 1e4, 2, 70, 10), spec);
    ReferenceOptions every;
    every.visitEveryTexel = true;
    const ReferenceImage fast = computeReference(gpuContext(), gpuCompiler(), scene);
    const ReferenceImage slow = computeReference(gpuContext(), gpuCompiler(), scene, every);
    CHECK(fast.rgb == slow.rgb);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("one pass of 2048 samples equals 32 passes of 64 (no truncated loops)") {
  // The same sample indices give the same samples, so the running means agree to float rounding. Guards
  // against lavapipe's per-invocation loop cap silently ending the sample loop of a long pass.
  const Scene scene = sceneWith(smoothSky(32, 16), "ggx", {}, 16);
  for (const char* sequence : {"random", "sobol"}) {
    MethodSpec spec;
    spec.sequence = sequence;
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    Renderer once(gpuContext(), gpuCompiler(), scene, method, 9),
        many(gpuContext(), gpuCompiler(), scene, method, 9);
    once.runPass(2048);
    for (int i = 0; i < 32; ++i) many.runPass(64);
    const auto a = once.meanRgb(), b = many.meanRgb();
    double worst = 0.0;
    for (size_t i = 0; i < a.size(); ++i)
      worst = std::max(worst, double(std::abs(a[i] - b[i])) / (std::abs(b[i]) + 1e-3));
    INFO(sequence << ": worst relative difference " << worst);
    CHECK(worst < 1e-4);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("every method converges to the convolution reference (z-test)") {
  struct Case {
    std::string name;
    EnvImage env;
    std::string brdf;
    std::vector<std::pair<std::string, std::string>> params;
  };
  const Case cases[] = {
      {"lambert/smooth", smoothSky(32, 16), "lambert", {}},
      {"ggx a=0.3 metallic=0.5/smooth",
       smoothSky(32, 16),
       "ggx",
       {{"roughness", "0.3"}, {"metallic", "0.5"}}},
      {"ggx a=0.15/sun+zero", sunAndZeroHalf(32, 16), "ggx", {{"roughness", "0.15"}, {"metallic", "1"}}},
  };
  // About 250 z-values (cases x methods x sequences x channels); |z| < 5.5 has a two-sided false-alarm rate
  // of 3.8e-8 each, 1e-5 for the family, while a bias of 5.5 standard errors (here ~1e-3 relative) fails.
  const double zBound = 5.5;
  for (const auto& c : cases)
    checkConvergesToReference(sceneWith(c.env, c.brdf, c.params, 24), c.name, zBound);
}

TEST_CASE("MSE falls like 1/N with random sampling") {
  const Scene scene = sceneWith(smoothSky(32, 16), "ggx", {{"roughness", "0.3"}, {"metallic", "0.5"}}, 32);
  const ReferenceImage ref = computeReference(gpuContext(), gpuCompiler(), scene);
  for (const char* name : {"env-cdf", "mis"}) {
    MethodSpec spec;
    spec.method = name;
    spec.sequence = "random";  // the default, `sobol`, is not i.i.d.: its MSE falls faster than variance / N
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(method.label());
    Renderer renderer(gpuContext(), gpuCompiler(), scene, method, 5);
    std::vector<double> mseTimesN;
    for (int n = 16, done = 0; n <= 1024; n *= 4) {
      while (done < n) renderer.runPass(16), done += 16;
      const ErrorMetrics e = compareToReference(scene.gbuffer, renderer.meanRgb(), ref.rgb);
      // Expected MSE = mean per-pixel variance / N: the ratio must stay near 1 at every N.
      const auto var = renderer.varianceRgb();
      double meanVar = 0;
      for (size_t i = 0; i < scene.gbuffer.pixels.size(); ++i)
        if (scene.gbuffer.pixels[i].normal.w != 0.0f)
          for (int ch = 0; ch < 3; ++ch) meanVar += var[3 * i + ch];
      meanVar /= 3.0 * double(scene.gbuffer.objectPixelCount());
      const double ratio = e.mse * n / meanVar;
      INFO("N = " << n << ": MSE " << e.mse << ", mean variance / N " << meanVar / n);
      CHECK(ratio > 0.75);
      CHECK(ratio < 1.33);
      mseTimesN.push_back(e.mse * n);
    }
    // The slope of log MSE against log N between 16 and 1024 spp is -1 within the noise.
    const double slope =
        std::log(mseTimesN.back() / 1024.0 / (mseTimesN.front() / 16.0)) / std::log(1024.0 / 16.0);
    CHECK(slope == doctest::Approx(-1.0).epsilon(0.1));
  }
  checkNoNewValidationErrors();
}

TEST_CASE("hard cases: no NaN or Inf for any method") {
  EnvImage broken = smoothSky(32, 16);
  broken.rgb[0] = std::nanf("");
  broken.rgb[10] = INFINITY;
  broken.rgb[20] = -INFINITY;
  broken.rgb[30] = -5.0f;
  const SanitizeReport report = sanitize(broken);
  CHECK(report.total() == 4);
  struct Case {
    std::string name;
    EnvImage env;
    std::string brdf;
    std::vector<std::pair<std::string, std::string>> params;
  };
  const Case cases[] = {
      {"sun 1e6 + zero half, lambert", sunAndZeroHalf(64, 32), "lambert", {}},
      {"sun 1e6 + zero half, ggx a=1e-3", sunAndZeroHalf(64, 32), "ggx", {{"roughness", "0.001"}}},
      {"pole energy, ggx a=0.05 dielectric",
       poleEnergy(64, 32),
       "ggx",
       {{"roughness", "0.05"}, {"metallic", "0"}}},
      {"sanitized NaN/Inf/negative, ggx", broken, "ggx", {}},
  };
  for (const auto& c : cases) {
    // 48 px: the sphere's silhouette supplies grazing pixels (n . wo -> 0).
    checkFiniteForEveryMethod(sceneWith(c.env, c.brdf, c.params, 48), c.name, 23);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("shader compiler: errors name the part file and line; the SPIR-V cache is used") {
  const auto dir = std::filesystem::temp_directory_path() / ("iblx-cache-test-" + std::to_string(::getpid()));
  ShaderCompiler compiler(dir);
  compiler.addSource("test/broken_part.glsl",
                     "// a comment\nvec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {\n"
                     "  return undeclaredThing;\n}\n");
  KernelParts parts{
      "integrate.comp",
      {"sequence/random.glsl", "test/broken_part.glsl", "brdf/lambert.glsl", "strategy/single_env.glsl"},
      paramBlockGlsl(findBrdf("lambert")),
      {}};
  try {
    compiler.compile(assemblePrelude(parts), "broken");
    FAIL("expected a compile error");
  } catch (const Error& e) {
    const std::string message = e.what();
    INFO(message);
    CHECK(message.find("test/broken_part.glsl:3") != std::string::npos);
    CHECK(message.find("undeclaredThing") != std::string::npos);
  }
  parts.parts[1] = "env_technique/uniform.glsl";
  const auto first = compiler.compile(assemblePrelude(parts), "ok");
  CHECK(compiler.compilations() == 2);
  ShaderCompiler again(dir);  // same sources: every source is part of the key
  again.addSource("test/broken_part.glsl",
                  "// a comment\nvec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {\n"
                  "  return undeclaredThing;\n}\n");
  const auto second = again.compile(assemblePrelude(parts), "ok");
  CHECK(again.cacheHits() == 1);
  CHECK(first == second);
  std::filesystem::remove_all(dir);
}

TEST_CASE("a part that reads a table its builder did not provide, or at another width, fails naming it") {
  KernelParts parts{
      "integrate.comp",
      {"sequence/random.glsl", "env_technique/env_cdf.glsl", "brdf/lambert.glsl", "strategy/single_env.glsl"},
      paramBlockGlsl(findBrdf("lambert")),
      {}};
  CHECK_THROWS_WITH_AS(
      compileKernel(gpuCompiler(), parts, "no tables"),
      doctest::Contains("env_technique/env_cdf.glsl:10: the part reads table 'envCdf', which no builder"),
      Error);
  // env-cdf's tables with the CDF at 4 words per element.
  TechniqueData wrongWidth = envCdfTechniqueData(constantEnv(8, 4, 1.0f));
  wrongWidth.tables[0].words = 4;
  parts.bindTables(kEnvTechniqueSet, 0, wrongWidth, "env technique env-cdf");
  CHECK_THROWS_WITH_AS(
      compileKernel(gpuCompiler(), parts, "wrong width"),
      doctest::Contains("the part reads table 'envCdf' with 1-word elements, but env technique "
                        "env-cdf provides 4-word elements"),
      Error);
}

TEST_CASE("ris: one candidate is the env technique's own estimator; more candidates stay unbiased") {
  // With M = 1 the one candidate is kept, and sum(w) / M = mean(f) cos cancels: the estimate is exactly
  // L f cos / p_env for the same u, so the images match to float rounding.
  const Scene scene = sceneWith(smoothSky(32, 16), "ggx", {{"roughness", "0.3"}}, 24);
  for (const char* env : {"env-cdf", "env-hier"}) {
    CAPTURE(env);
    MethodSpec ris{"ris", env};
    ris.risCandidates = 1;
    Renderer a(gpuContext(), gpuCompiler(), scene, resolveMethod(ris, *scene.brdf), 7);
    Renderer b(gpuContext(), gpuCompiler(), scene, resolveMethod({env}, *scene.brdf), 7);
    a.runPass(16);
    b.runPass(16);
    const auto x = a.meanRgb(), y = b.meanRgb();
    double worst = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i)
      worst = std::max(worst, std::abs(double(x[i]) - y[i]) / (y[i] + 1e-3));
    CHECK(worst < 1e-4);
  }
  // M = 32 against the reference (z-test), on a 1e6 sun with a zero half. Regression: a first version took
  // mean(f) cos as the target (not p_env mean(f) cos): sun candidates were then kept with probabilities far
  // below their share of the integral, and the image mean was off by z = -6.6 (-20 with 8x the samples).
  const Scene hard = sceneWith(sunAndZeroHalf(32, 16), "ggx", {{"roughness", "0.3"}}, 24);
  const ReferenceImage ref = computeReference(gpuContext(), gpuCompiler(), hard);
  MethodSpec ris{"ris", "env-cdf"};
  ris.risCandidates = 32;
  Renderer r(gpuContext(), gpuCompiler(), hard, resolveMethod(ris, *hard.brdf), 3);
  for (int pass = 0; pass < 8; ++pass) r.runPass(32);
  const MeanErrorZTest z = zTest(hard, r, ref.rgb);
  for (int c = 0; c < 3; ++c) CHECK(std::abs(z.z[c]) < 5.5);
  CHECK(r.nonFiniteSamples() == 0);
  checkNoNewValidationErrors();
}

TEST_CASE("reference: narrow lobes are integrated in full (regression: truncated loops on lavapipe)") {
  // GGX a = 0.01 on a 64 x 32 map needs 20 x 20 sub-cells in each texel near the mirror direction. A first
  // version let one dispatch run 2048 texels per pixel plus their sub-cells, past lavapipe's cap on loop
  // iterations per invocation: loops ended early, and the reference came out low (VNDF sampling, nearly exact
  // on a smooth sky, then sat at z = +384). Dispatches are now sized by their worst-case iteration count.
  const Scene scene = sceneWith(smoothSky(64, 32), "ggx", {{"roughness", "0.01"}, {"metallic", "1"}}, 24);
  const ReferenceImage ref = computeReference(gpuContext(), gpuCompiler(), scene);
  CHECK(ref.fineSubdivisions >= 16);
  Renderer renderer(gpuContext(), gpuCompiler(), scene, resolveMethod({"brdf"}, *scene.brdf), 3);
  for (int pass = 0; pass < 8; ++pass) renderer.runPass(64);
  const MeanErrorZTest t = zTest(scene, renderer, ref.rgb);
  for (int c = 0; c < 3; ++c) {
    INFO("channel " << c << ": mean error " << t.meanError[c] << ", standard error " << t.standardError[c]);
    CHECK(std::abs(t.z[c]) < 5.5);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("setView: a renderer given another camera renders what a new renderer of that view renders") {
  // The viewer's orbit: only the G-buffer is uploaded again; tables, kernel and environment stay.
  SceneSpec spec;
  spec.width = spec.height = 32;
  const Scene front = makeScene(smoothSky(32, 16), spec);
  spec.camera = {.azimuthDeg = 70.0, .elevationDeg = 35.0, .zoom = 1.3};
  const Scene orbited = makeScene(smoothSky(32, 16), spec);
  MethodSpec methodSpec;
  methodSpec.method = "env-cdf";
  const ResolvedMethod method = resolveMethod(methodSpec, *front.brdf);
  Renderer moved(gpuContext(), gpuCompiler(), front, method, 5),
      fresh(gpuContext(), gpuCompiler(), orbited, method, 5);
  for (int i = 0; i < 3; ++i) moved.runPass(16);
  moved.setView(orbited);
  CHECK(moved.samplesPerPixel() == 0);
  for (int i = 0; i < 3; ++i) moved.runPass(16), fresh.runPass(16);
  CHECK(moved.meanRgb() == fresh.meanRgb());  // same samples, same G-buffer: bit-identical
  // The views really differ (the test could not pass by accident).
  Renderer still(gpuContext(), gpuCompiler(), front, method, 5);
  for (int i = 0; i < 3; ++i) still.runPass(16);
  CHECK(still.meanRgb() != fresh.meanRgb());
  // Anything but the G-buffer needs a new renderer.
  spec.width = 16;
  const Scene smaller = makeScene(smoothSky(32, 16), spec);
  CHECK_THROWS_WITH_AS(moved.setView(smaller), doctest::Contains("image size"), Error);
  spec.width = 32;
  spec.envRotationDeg = 90.0;
  const Scene rotated = makeScene(smoothSky(32, 16), spec);
  CHECK_THROWS_WITH_AS(moved.setView(rotated), doctest::Contains("only the G-buffer"), Error);
  checkNoNewValidationErrors();
}

TEST_CASE("product tables: their own kernel builds them again at every restart") {
  // The stored tables are built by a separate kernel dispatched at the start of an accumulation: after new
  // parameter values (a narrower lobe, whose tables also split nodes) the image equals a fresh renderer's,
  // which it would not if the tables of the first values were still sampled.
  const EnvImage env = smoothSky(64, 32);
  const Scene rough = sceneWith(env, "ggx", {{"roughness", "0.5"}}, 24);
  const Scene shiny = sceneWith(env, "ggx", {{"roughness", "0.05"}}, 24);
  MethodSpec spec;
  spec.method = "product";
  spec.sequence = "sobol";
  const ResolvedMethod method = resolveMethod(spec, *rough.brdf);
  Renderer renderer(gpuContext(), gpuCompiler(), rough, method, 3);
  REQUIRE(renderer.productTableChunks() == 1);
  renderer.runPass(4);
  const auto roughImage = renderer.meanRgb();
  renderer.setParams(shiny.params);
  renderer.runPass(4);
  renderer.runPass(4);
  Renderer fresh(gpuContext(), gpuCompiler(), shiny, method, 3);
  fresh.runPass(4);
  fresh.runPass(4);
  CHECK(renderer.meanRgb() == fresh.meanRgb());
  CHECK(fresh.meanRgb() != roughImage);
  checkNoNewValidationErrors();
}

TEST_CASE("product tables: split over buffers, read in place, copied or rebuilt, the image is the same") {
  // A device whose largest buffer holds 1 MiB (670 pixels' tables) splits a 50 x 50 image's tables over four
  // buffers (625 pixels each), and rebuilds a 64 x 64 image's (seven would be needed) in every dispatch. A
  // wrong chunk or offset would pair a pixel with another pixel's table from the second pass on; passes of 4
  // samples read the stored table in place, passes of 64 copy it. The same seed gives the same samples, so
  // every image agrees with the one-buffer image to float rounding.
  MethodSpec spec;
  spec.method = "product";
  spec.sequence = "sobol";
  ::setenv("IBLX_MAX_BUFFER_MIB", "1", 1);
  std::optional<VulkanContext> small;
  try {
    small.emplace(ContextOptions{"", Validation::Auto});
  } catch (...) {
    ::unsetenv("IBLX_MAX_BUFFER_MIB");
    throw;
  }
  ::unsetenv("IBLX_MAX_BUFFER_MIB");
  // Maps of 64 x 32 and 128 x 64 texels: 32 x 16 nodes of 2 x 2 and 4 x 4 texels, so the refinement's records
  // (one and two levels below the table's) are stored and read too; a 64 x 26 map's 32 x 13 nodes leave the
  // stored rows' sums a padding half (an odd count), against the table rebuilt in private memory.
  for (const auto& [size, chunks, mapWidth, mapRows] :
       {std::tuple{50, 4, 64, 32}, std::tuple{50, 4, 128, 64}, std::tuple{64, 0, 64, 32},
        std::tuple{64, 0, 64, 26}}) {
    CAPTURE(size);
    CAPTURE(mapWidth);
    CAPTURE(mapRows);
    const Scene scene = sceneWith(smoothSky(mapWidth, mapRows), "ggx", {{"roughness", "0.1"}}, size);
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    Renderer tested(*small, gpuCompiler(), scene, method, 5),
        whole(gpuContext(), gpuCompiler(), scene, method, 5);
    CHECK(tested.productTableChunks() == std::size_t(chunks));
    CHECK(whole.productTableChunks() == 1);
    for (uint32_t spp : {64u, 4u, 64u, 4u}) tested.runPass(spp), whole.runPass(spp);
    const auto a = tested.meanRgb(), b = whole.meanRgb();
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      worst = std::max(worst, double(std::abs(a[i] - b[i])) / (std::abs(b[i]) + 1e-3));
    INFO("worst relative difference " << worst);
    CHECK(worst < 1e-5);
  }
  CHECK(small->validationMessages().empty());
}
