// BRDF Explorer .brdf files on the GPU (engine/scene/analytic_brdf.h): a GGX file evaluates like the
// built-in ggx, names the snippet shares with the kernels or GLSL compile, compile errors name the file's own
// lines, brdf-tab passes chi-square and converges to the reference, the isFunc hook, .bparam files, and the
// guard against negative and non-finite values.
#include "engine/io/brdf_file.h"
#include "engine/scene/analytic_brdf.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/scene/brdf_params.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"
#include "tests/io/scratch_files.h"
#include "tests/support/chi2.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <random>

using namespace iblx;
using namespace iblx::test;

namespace {

// The built-in ggx with metallic = 1 (shaders/brdf/ggx.glsl), written as a BRDF Explorer file. Its helpers
// reuse names of the kernels' own (ggxD, fresnelSchlick) and a GLSL built-in (reflect), which the loader
// renames.
const char* kGgxFile = R"(analytic
# GGX metal, the same formulas as iblx's built-in ggx with metallic = 1
::begin parameters
color f0 0.95 0.64 0.54
float roughness 0.001 1 0.25
::end parameters

::begin shader
const float PI = 3.14159265358979;
float ggxD(vec3 h, float a) {
    if (h.z <= 0.0) return 0.0;
    float e = dot(h.xy, h.xy) / (a * a) + h.z * h.z;
    return 1.0 / (PI * a * a * e * e);
}
float lambda(vec3 w, float a) {
    float c2 = w.z * w.z;
    float t2 = max(1.0 - c2, 0.0) / c2;
    return 0.5 * (-1.0 + sqrt(1.0 + a * a * t2));
}
vec3 fresnelSchlick(vec3 r0, float c) {
    float m = clamp(1.0 - c, 0.0, 1.0);
    float m2 = m * m;
    return r0 + (1.0 - r0) * (m2 * m2 * m);
}
vec3 reflect(vec3 I, vec3 N) { return I - 2.0 * dot(N, I) * N; }
vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )
{
    vec3 wi = vec3(dot(L, X), dot(L, Y), dot(L, N));
    vec3 wo = vec3(dot(V, X), dot(V, Y), dot(V, N));
    if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
    vec3 h = normalize(wi + wo);
    float g2 = 1.0 / (1.0 + lambda(wi, roughness) + lambda(wo, roughness));
    vec3 unused = reflect(-wo, vec3(0.0, 0.0, 1.0));
    return fresnelSchlick(f0, dot(wi, h)) * (ggxD(h, roughness) * g2 / (4.0 * wi.z * wo.z));
}
::end shader
)";

// Lambert with its own cosine sampler, under iblx's isFunc contract (iblxV, pdfBRDF).
const char* kLambertIsFunc = R"(analytic
::begin parameters
color albedo 0.7 0.7 0.7
::end parameters
::begin shader
vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y ) { return albedo / 3.14159265358979; }
::end shader
::begin isFunc
vec3 sampleBRDF( float u, float v, vec3 N, vec3 X, vec3 Y, out vec3 wi, out float pdf )
{
    float r = sqrt(u), phi = 6.28318530717959 * v;
    float z = sqrt(max(1.0 - u, 0.0));
    wi = r * cos(phi) * X + r * sin(phi) * Y + z * N;
    pdf = z / 3.14159265358979;
    return pdf > 0.0 ? BRDF(wi, iblxV, N, X, Y) * z / pdf : vec3(0.0);
}
float pdfBRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y ) { return max(dot(L, N), 0.0) / 3.14159265358979; }
::end isFunc
)";

std::filesystem::path writeFile(const ScratchDir& dir, const std::string& name, const std::string& text) {
  const auto path = dir.file(name);
  std::ofstream(path) << text;
  return path;
}

// Random pairs above the horizon, grazing ones included.
void randomPairs(std::size_t count, std::vector<glm::dvec3>& wi, std::vector<glm::dvec3>& wo) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto direction = [&] {
    const double z = std::max(1e-3, u(rng)), phi = 2.0 * 3.14159265358979 * u(rng);
    const double r = std::sqrt(1.0 - z * z);
    return glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
  };
  for (std::size_t i = 0; i < count; ++i) wi.push_back(direction()), wo.push_back(direction());
}

}  // namespace

TEST_CASE("analytic brdf: a GGX .brdf evaluates like the built-in ggx") {
  ScratchDir dir;
  const auto path = writeFile(dir, "ggx_metal.brdf", kGgxFile);
  std::vector<glm::dvec3> wi, wo;
  randomPairs(4000, wi, wo);
  for (const char* roughness : {"0.05", "0.5"}) {
    CAPTURE(roughness);
    const Scene file = sceneWith(constantEnv(2, 1, 1.0f), path.string(), {{"roughness", roughness}}, 1);
    const Scene builtin =
        sceneWith(constantEnv(2, 1, 1.0f), "ggx", {{"roughness", roughness}, {"metallic", "1"}}, 1);
    CHECK(file.brdf->name == "ggx_metal");
    CHECK(file.brdf->bestSampler == "brdf-tab");
    const auto a = evaluateBrdf(gpuContext(), gpuCompiler(), file, wi, wo);
    const auto b = evaluateBrdf(gpuContext(), gpuCompiler(), builtin, wi, wo);
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(a[i][c] - b[i][c]) / (b[i][c] + 1e-3));
    CHECK(worst < 1e-4);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("analytic brdf: GLSL errors and reserved names name the file's own line") {
  ScratchDir dir;
  // Line 9 holds the error; comment and blank lines before it are dropped by the parser but still counted.
  const auto bad =
      writeFile(dir, "typo.brdf",
                "analytic\n::begin parameters\nfloat n 1 10 2\n::end parameters\n\n::begin shader\n"
                "# a comment\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n"
                "  return vec3(undeclaredThing * n);\n}\n::end shader\n");
  const Scene scene = sceneWith(constantEnv(2, 1, 1.0f), bad.string(), {}, 1);
  const std::string message = errorMessage([&] {
    const glm::dvec3 z(0.0, 0.0, 1.0);
    evaluateBrdf(gpuContext(), gpuCompiler(), scene, std::span(&z, 1), std::span(&z, 1));
  });
  CHECK_MESSAGE(contains(message, "typo.brdf:9"), message);
  CHECK_MESSAGE(contains(message, "undeclaredThing"), message);

  const auto reserved =
      writeFile(dir, "reserved.brdf",
                "analytic\n::begin parameters\nfloat smoothstep 0 1 0\n::end parameters\n"
                "::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return "
                "vec3(0); }\n::end shader\n");
  CHECK(contains(errorMessage([&] { loadBrdfArgument(reserved.string()); }),
                 "reserved.brdf:3: parameter name "
                 "'smoothstep' is reserved"));
  const auto noBrdf = writeFile(dir, "nobrdf.brdf",
                                "analytic\n::begin shader\nvec3 brdf(vec3 L) { return L; }\n::end shader\n");
  CHECK(contains(errorMessage([&] { loadBrdfArgument(noBrdf.string()); }),
                 "nobrdf.brdf:3: the shader section "
                 "defines no 'vec3 BRDF"));
}

TEST_CASE("analytic brdf: renaming keeps member calls and entry points") {
  std::vector<std::string> renamed;
  const std::string out = renameBuiltinRedefinitions(
      "float sqr(float x) { return x * x; }\nconst float PI = 3.14;\nfloat D(float alpha, vec3 h) { return "
      "alpha; }\n"
      "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { float a[2]; return vec3(sqr(PI) + a.length()); }",
      &renamed);
  // Function parameters are not globals: `alpha` may also be a BRDF parameter used elsewhere (regression).
  CHECK(renamed == std::vector<std::string>{"D", "PI", "sqr"});
  CHECK(contains(out, "float iblxUser_D(float alpha, vec3 h) { return alpha; }"));
  CHECK(contains(out, "float iblxUser_sqr(float x)"));
  CHECK(contains(out, "const float iblxUser_PI = 3.14;"));
  CHECK(contains(out, "vec3(iblxUser_sqr(iblxUser_PI) + a.length())"));
  CHECK(contains(out, "vec3 BRDF(vec3 L"));
}

TEST_CASE("analytic brdf: brdf-tab passes chi-square on a GGX .brdf, grazing views included") {
  ScratchDir dir;
  const auto path = writeFile(dir, "ggx_metal.brdf", kGgxFile);
  const double views[] = {0.0, 45.0, 80.0, 88.0};
  for (const double view : views) {
    CAPTURE(view);
    const double t = view * 3.14159265358979 / 180.0;
    BrdfTechniqueProbe probe("brdf-tab", path.string(), {{"roughness", "0.1"}},
                             {std::sin(t) * 0.8, std::sin(t) * 0.6, std::cos(t)});
    const auto samples = probe.sample(uniformPoints(200000, 3));
    std::vector<glm::dvec3> directions;
    for (const auto& s : samples)
      if (s.pdf > 0.0) directions.push_back(s.direction);
    checkChi2AgainstPdf(probe, directions, int(std::size(views)), "brdf-tab-ggx-file");
  }
  checkNoNewValidationErrors();
}

TEST_CASE("analytic brdf: every method converges to the reference on a GGX .brdf (z-test)") {
  ScratchDir dir;
  const auto path = writeFile(dir, "ggx_metal.brdf", kGgxFile);
  // Every registry method once (a BRDF part beside techniques tested on the built-ins in every combination).
  checkConvergesToReference(sceneWith(sunAndZeroHalf(32, 16), path.string(), {{"roughness", "0.2"}}, 24),
                            "ggx .brdf/sun+zero", 5.5, MethodSet::EveryMethod);
}

TEST_CASE("analytic brdf: the isFunc hook samples, and a file without pdfBRDF falls back to brdf-tab") {
  ScratchDir dir;
  const auto path = writeFile(dir, "lambert_is.brdf", kLambertIsFunc);
  const Scene scene = sceneWith(constantEnv(16, 8, 1.0f), path.string(), {}, 24);
  CHECK(scene.brdf->hasSampleHook);
  CHECK(scene.brdf->bestSampler == "isfunc");
  for (const double view : {0.0, 70.0}) {
    const double t = view * 3.14159265358979 / 180.0;
    BrdfTechniqueProbe probe("isfunc", path.string(), {}, {std::sin(t), 0.0, std::cos(t)});
    const auto samples = probe.sample(uniformPoints(100000, 4));
    std::vector<glm::dvec3> directions;
    std::size_t mismatches = 0;
    for (const auto& s : samples) {
      if (!(s.pdf > 0.0)) continue;
      directions.push_back(s.direction);
      mismatches += std::abs(s.pdf - s.pdfLookup) > 1e-4 * s.pdf;
    }
    CHECK(directions.size() > 99000);
    CHECK(mismatches == 0);
    checkChi2AgainstPdf(probe, directions, 2, "isfunc-lambert");
  }
  checkWhiteFurnace(scene, 0.7, 4, 5.0);

  std::string noPdf = kLambertIsFunc;
  noPdf.erase(noPdf.find("float pdfBRDF"), noPdf.find("::end isFunc") - noPdf.find("float pdfBRDF"));
  const auto fallback = writeFile(dir, "lambert_nopdf.brdf", noPdf);
  WarningCapture warnings;
  const LoadedBrdf loaded = loadBrdfArgument(fallback.string());
  CHECK_FALSE(loaded.info->hasSampleHook);
  CHECK(loaded.info->bestSampler == "brdf-tab");
  REQUIRE(warnings.messages.size() == 1);
  CHECK(contains(warnings.messages[0], "defines sampleBRDF but no pdfBRDF"));
  CHECK_THROWS_AS(resolveMethod({"brdf", "", "isfunc"}, *loaded.info), Error);
}

TEST_CASE("analytic brdf: a .bparam sets the defaults of the file it names") {
  ScratchDir dir;
  const auto path = writeFile(dir, "ggx_metal.brdf", kGgxFile);
  const LoadedBrdf model = loadBrdfArgument(path.string());
  ParamValues values = resolveParams(*model.info, {{"roughness", "0.5"}, {"f0", "0.2,0.3,0.4"}});
  writeBparam(dir.file("rough.bparam"), "ggx_metal.brdf", model.info->params, values);
  WarningCapture warnings;
  const LoadedBrdf saved = loadBrdfArgument(dir.file("rough.bparam").string());
  CHECK(warnings.messages.empty());  // regression: unused channels of a float were "clamped" with a warning
  CHECK(saved.info->name == "rough");
  CHECK(saved.file == path);
  const ParamValues defaults = resolveParams(*saved.info, {});
  CHECK(float(defaults.at("roughness")[0]) == 0.5f);
  CHECK(float(defaults.at("f0")[2]) == 0.4f);
  // --param still overrides a saved value.
  CHECK(resolveParams(*saved.info, {{"roughness", "0.1"}}).at("roughness")[0] == 0.1);
}

TEST_CASE("analytic brdf: negative and non-finite values count as 0, and a render stays finite") {
  ScratchDir dir;
  const auto path =
      writeFile(dir, "broken.brdf",
                "analytic\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n"
                "  float zero = dot(L, N) * 0.0;\n"
                "  return vec3(zero / zero, -1.0, 1.0 / zero);\n}\n::end shader\n");
  const Scene scene = sceneWith(smoothSky(16, 8), path.string(), {}, 16);
  const glm::dvec3 z(0.0, 0.0, 1.0);
  const auto f = evaluateBrdf(gpuContext(), gpuCompiler(), scene, std::span(&z, 1), std::span(&z, 1));
  CHECK(f[0] == glm::dvec3(0.0));
  for (const char* method : {"env-cdf", "mis"}) {
    Renderer renderer(gpuContext(), gpuCompiler(), scene, resolveMethod({method}, *scene.brdf), 1);
    renderer.runPass(16);
    CHECK(renderer.nonFiniteSamples() == 0);
    for (float v : renderer.meanRgb()) CHECK(std::isfinite(v));
  }
  checkNoNewValidationErrors();
}

TEST_CASE("analytic brdf: new parameter values restart accumulation without recompiling") {
  ScratchDir dir;
  const auto path = writeFile(dir, "ggx_metal.brdf", kGgxFile);
  const EnvImage env = smoothSky(32, 16);
  const Scene rough = sceneWith(env, path.string(), {{"roughness", "0.5"}}, 16);
  const Scene shiny = sceneWith(env, path.string(), {{"roughness", "0.1"}}, 16);
  const ResolvedMethod method = resolveMethod({"env-cdf"}, *rough.brdf);
  Renderer renderer(gpuContext(), gpuCompiler(), rough, method, 4);
  renderer.runPass(8);
  const int compilations = gpuCompiler().compilations();
  renderer.setParams(shiny.params);
  CHECK(renderer.samplesPerPixel() == 0);
  renderer.runPass(8);
  CHECK(gpuCompiler().compilations() == compilations);
  // The same image as a renderer made with those values (same seed, same samples).
  Renderer fresh(gpuContext(), gpuCompiler(), shiny, method, 4);
  fresh.runPass(8);
  CHECK(renderer.meanRgb() == fresh.meanRgb());
  ParamValues bad = shiny.params;
  bad["roughness"][0] = 2.0;
  CHECK_THROWS_AS(renderer.setParams(bad), Error);
  bad.erase("roughness");
  CHECK_THROWS_AS(renderer.setParams(bad), Error);
  checkNoNewValidationErrors();
}
