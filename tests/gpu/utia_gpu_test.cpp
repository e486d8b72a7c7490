// UTIA and MIT CSAIL measured BRDFs on the GPU, with files written by the project's own tabulation
// (tabulateUtia, tabulateMit): the kernels' lookups against the CPU reference lookups (UTIA with the colour
// convention's parameters), the white furnace of a tabulated Lambert for every method, tabulated against
// analytic GGX, and an anisotropic material (BRDF Explorer's Ward) whose tabulation follows the tangent
// frame.
#include "engine/core/assets.h"
#include "engine/io/mit_brdf.h"
#include "engine/io/utia.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/render/reference.h"
#include "engine/scene/measured_brdfs.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"
#include "tests/io/scratch_files.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <numbers>

using namespace iblx;
using namespace iblx::test;

namespace {

// Tabulated once per test run into a scratch directory that lives as long as the process.
std::filesystem::path synthesizeUtia(const std::string& name, const std::string& brdf,
                                     std::vector<std::pair<std::string, std::string>> params) {
  static ScratchDir dir;
  static std::map<std::string, std::filesystem::path> made;
  if (auto it = made.find(name); it != made.end()) return it->second;
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), brdf, std::move(params), 1);
  const auto path = dir.file(name + ".bin");
  writeUtia(path, tabulateUtia(gpuContext(), gpuCompiler(), analytic));
  return made[name] = path;
}

const MitDims kMitDims{18, 18, 72, 36, false};

// `unmeasured`: every this-many-th bin is written as -1 (unmeasured) in its green channel; 0: none.
std::filesystem::path synthesizeMit(const std::string& name, const std::string& brdf,
                                    std::vector<std::pair<std::string, std::string>> params,
                                    std::size_t unmeasured = 0) {
  static ScratchDir dir;
  static std::map<std::string, std::filesystem::path> made;
  if (auto it = made.find(name); it != made.end()) return it->second;
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), brdf, std::move(params), 1);
  std::vector<float> values = tabulateMit(gpuContext(), gpuCompiler(), analytic, kMitDims);
  if (unmeasured > 0)
    for (std::size_t i = 0; i < kMitDims.bins(); i += unmeasured) values[kMitDims.bins() + i] = -1.0f;
  const auto path = dir.file(name + ".dat");
  writeMitBrdf(path, kMitDims, values);
  return made[name] = path;
}

}  // namespace

TEST_CASE("utia: the GPU lookup agrees with the CPU reference lookup, under the colour convention too") {
  ScratchDir dir;
  std::vector<double> values(3 * kUtiaEntries);
  for (std::size_t k = 0; k < values.size(); ++k) values[k] = 0.01 + double((k * 7919) % 10007) / 10007.0;
  const auto path = dir.file("distinct.bin");
  writeUtia(path, values);
  const auto u = uniformPoints(2 * 20000, 31);
  std::vector<glm::dvec3> wi, wo;
  for (std::size_t i = 0; i + 1 < u.size(); i += 2) {
    wi.push_back(glm::dvec3(glm::vec3(hemisphere(u[i]))));  // the GPU receives floats
    wo.push_back(glm::dvec3(glm::vec3(hemisphere(u[i + 1]))));
  }
  for (const auto& params : std::vector<std::vector<std::pair<std::string, std::string>>>{
           {}, {{"prescale", "0.5"}, {"srgb", "1"}, {"scale", "3"}}}) {
    const Scene scene = sceneWith(constantEnv(2, 1, 0.0f), path.string(), params, 1);
    REQUIRE(scene.brdf->evalPart == "brdf/utia.glsl");
    const UtiaBrdf brdf = loadUtia(path);
    const UtiaConvention convention = utiaConvention(scene.params);
    const auto gpu = evaluateBrdf(gpuContext(), gpuCompiler(), scene, wi, wo);
    double worst = 0.0;
    for (std::size_t i = 0; i < wi.size(); ++i) {
      const glm::dvec3 cpu = evalUtia(brdf, wi[i], wo[i], convention);
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(gpu[i][c] - cpu[c]) / (cpu[c] + 1e-6));
    }
    INFO("worst relative difference " << worst);
    // Float angles against double ones move a continuous interpolation by little.
    CHECK(worst < 2e-3);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("utia: a tabulated Lambert under the white furnace gives its albedo, for every method") {
  const auto path = synthesizeUtia("lambert07", "lambert", {{"albedo", "0.7"}});
  checkWhiteFurnace(sceneWith(constantEnv(16, 8, 1.0f), path.string(), {}, 24), 0.7, 8, 5.5,
                    MethodSet::EveryMethod);
}

TEST_CASE("utia: tabulated GGX renders like the analytic GGX within the tabulation error") {
  const std::vector<std::pair<std::string, std::string>> params{{"roughness", "0.5"}, {"metallic", "1"}};
  const auto path = synthesizeUtia("ggx05", "ggx", params);
  const Scene analytic = sceneWith(smoothSky(64, 32), "ggx", params, 24);
  const Scene measured = sceneWith(smoothSky(64, 32), path.string(), {}, 24);
  const ReferenceComparison d = compareReferences(analytic, measured);
  INFO("image sums measured / analytic " << d.sumRatio << ", worst pixel relative difference "
                                         << d.worstRelative);
  // A 15-degree grid: the tabulation error is the grid's, largest at grazing views (clamped above 75
  // degrees). Measured: 0.2 % of the image mean, 10 % at the worst pixel.
  CHECK(std::abs(d.sumRatio - 1.0) < 0.01);
  CHECK(d.worstRelative < 0.2);
  checkNoNewValidationErrors();
}

TEST_CASE("utia: a tabulated anisotropic material follows the tangent frame") {
  const std::string ward = assetPath("brdf/ward.brdf").string();
  const auto path = synthesizeUtia("ward", ward, {});
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), ward, {}, 1);
  const Scene measured = sceneWith(constantEnv(2, 1, 0.0f), path.string(), {}, 1);
  // A view at 45 degrees and a light at 30 degrees opposite, so the half vector leans 7.5 degrees towards the
  // tangent; then both turned by 90 degrees about the normal, so it leans towards the bitangent: Ward's
  // alphaX 0.15 x alphaY 0.4 lobe falls off faster along the tangent. All four are grid directions.
  const glm::dvec3 wo = utiaDirection(3, 0), wi = utiaDirection(2, 24);
  // Turned by 90 degrees: 12 steps of 7.5 degrees in phi.
  const std::vector<glm::dvec3> wis{wi, utiaDirection(2, 36)}, wos{wo, utiaDirection(3, 12)};
  const auto f = evaluateBrdf(gpuContext(), gpuCompiler(), analytic, wis, wos);
  const auto g = evaluateBrdf(gpuContext(), gpuCompiler(), measured, wis, wos);
  INFO("Ward " << f[0].x << " / " << f[1].x << ", tabulated " << g[0].x << " / " << g[1].x);
  CHECK(std::abs(f[1].x / f[0].x - 1.0) > 0.3);  // the analytic lobe is anisotropic
  for (int k = 0; k < 2; ++k) CHECK(g[k].x == doctest::Approx(f[k].x).epsilon(0.02));  // grid points
  // Turning the tangent turns the highlight: the tabulated material is as anisotropic as the analytic one.
  CHECK(g[1].x / g[0].x == doctest::Approx(f[1].x / f[0].x).epsilon(0.05));
  checkNoNewValidationErrors();
}

TEST_CASE("mit .dat: the GPU lookup agrees with the CPU reference lookup, with and without half data") {
  ScratchDir dir;
  const auto u = uniformPoints(2 * 20000, 41);
  std::vector<glm::dvec3> wi, wo;
  for (std::size_t i = 0; i + 1 < u.size(); i += 2) {
    wi.push_back(glm::dvec3(glm::vec3(hemisphere(u[i]))));
    wo.push_back(glm::dvec3(glm::vec3(hemisphere(u[i + 1]))));
  }
  for (const bool half : {false, true}) {
    CAPTURE(half);
    const MitDims dims{9, 10, 12, 16, half};
    std::vector<float> values(3 * dims.bins());
    for (std::size_t k = 0; k < values.size(); ++k) values[k] = float(k + 1) / float(values.size());
    const auto path = dir.file(half ? "half.dat" : "full.dat");
    writeMitBrdf(path, dims, values);
    const Scene scene = sceneWith(constantEnv(2, 1, 0.0f), path.string(), {{"scale", "2"}}, 1);
    REQUIRE(scene.brdf->evalPart == "brdf/mit.glsl");
    const MitBrdf brdf = loadMitBrdf(path);
    const auto gpu = evaluateBrdf(gpuContext(), gpuCompiler(), scene, wi, wo);
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < wi.size(); ++i)
      mismatches += glm::any(
          glm::greaterThan(glm::abs(gpu[i] - evalMitBrdf(brdf, wi[i], wo[i], 2.0)), glm::dvec3(1e-6)));
    INFO(mismatches << " of " << wi.size() << " pairs in another bin");
    // Float against double angles may pick the neighbouring bin within rounding of a bin edge: rare.
    CHECK(mismatches <= wi.size() / 1000);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("mit .dat: a tabulated Lambert under the white furnace gives its albedo, for every method") {
  const auto path = synthesizeMit("lambert07", "lambert", {{"albedo", "0.7"}});
  checkWhiteFurnace(sceneWith(constantEnv(16, 8, 1.0f), path.string(), {}, 24), 0.7, 8, 5.5,
                    MethodSet::EveryMethod);
}

TEST_CASE("mit .dat: a tabulated anisotropic material follows the tangent frame") {
  const std::string ward = assetPath("brdf/ward.brdf").string();
  const auto path = synthesizeMit("ward", ward, {});
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), ward, {}, 1);
  const Scene measured = sceneWith(constantEnv(2, 1, 0.0f), path.string(), {}, 1);
  // Bin centres: the half vector leaning towards the tangent, then turned by 90 degrees (9 phi_in bins).
  const MitDirectionPair a = mitBinCenter(kMitDims, 6, 9, 36, 0), b = mitBinCenter(kMitDims, 6, 9, 36, 9);
  const std::vector<glm::dvec3> wis{a.wi, b.wi}, wos{a.wo, b.wo};
  const auto f = evaluateBrdf(gpuContext(), gpuCompiler(), analytic, wis, wos);
  const auto g = evaluateBrdf(gpuContext(), gpuCompiler(), measured, wis, wos);
  INFO("Ward " << f[0].x << " / " << f[1].x << ", tabulated " << g[0].x << " / " << g[1].x);
  CHECK(std::abs(f[1].x / f[0].x - 1.0) > 0.3);
  for (int k = 0; k < 2; ++k) CHECK(g[k].x == doctest::Approx(f[k].x).epsilon(1e-4));  // bin centres
  checkNoNewValidationErrors();
}

TEST_CASE(
    "utia and mit: brdf-tab passes chi-square against its pdf on an anisotropic material, grazing included") {
  const std::string ward = assetPath("brdf/ward.brdf").string();
  // Three views over the two formats: normal incidence and grazing on the UTIA file, 40 degrees on the MIT
  // one.
  struct Case {
    std::filesystem::path file;
    double thetaO, phiO;
  };
  const Case cases[] = {{synthesizeUtia("ward", ward, {}), 0.0, 0.0},
                        {synthesizeUtia("ward", ward, {}), 80.0, 200.0},
                        {synthesizeMit("ward", ward, {}), 40.0, 30.0}};
  for (const Case& c : cases) {
    INFO(c.file.filename().string() << ", theta_o = " << c.thetaO);
    BrdfTechniqueProbe probe("brdf-tab", c.file.string(), {}, viewAt(c.thetaO, c.phiO));
    const auto samples = probe.sample(uniformPoints(100000, 7));
    std::vector<glm::dvec3> directions;
    for (const auto& s : samples)
      if (s.pdf > 0.0) directions.push_back(s.direction);
    checkChi2AgainstPdf(probe, directions, int(std::size(cases)), "brdf-tab-measured");
  }
  checkNoNewValidationErrors();
}

TEST_CASE("utia and mit: every method converges to the reference, with unmeasured bins and under a 1e6 sun") {
  const std::string ward = assetPath("brdf/ward.brdf").string();
  const double zBound = 5.5;  // as in render_gpu_test.cpp
  checkConvergesToReference(
      sceneWith(sunAndZeroHalf(32, 16), synthesizeUtia("ward", ward, {}).string(), {}, 16),
      "utia ward/sun+zero", zBound, MethodSet::EveryMethod);
  checkConvergesToReference(
      sceneWith(sunAndZeroHalf(32, 16), synthesizeMit("ward-unmeasured", ward, {}, 20).string(), {}, 16),
      "mit ward with unmeasured bins/sun+zero", zBound, MethodSet::EveryMethod);
}
