// MERL measured BRDFs on the GPU, with synthetic materials written by the project's own tabulation
// (engine/render/brdf_tabulation.h): the kernel's lookup against the CPU reference lookup, the white furnace
// of a tabulated Lambert, tabulated against analytic GGX, both MERL techniques against their CPU twins and
// the chi-square test, convergence of every method to the reference, and no NaN/Inf with invalid entries.
#include "engine/core/error.h"
#include "engine/io/merl.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/render/reference.h"
#include "engine/sampling/brdf/merl_sampling.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"
#include "tests/io/scratch_files.h"
#include "tests/support/chi2.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <map>

using namespace iblx;
using namespace iblx::test;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// Synthetic materials, tabulated once per test run into a scratch directory that lives as long as the
// process.
std::filesystem::path synthesize(const std::string& name, const std::string& brdf,
                                 std::vector<std::pair<std::string, std::string>> params,
                                 MerlSynthOptions options = {}) {
  static ScratchDir dir;
  static std::map<std::string, std::filesystem::path> made;
  if (auto it = made.find(name); it != made.end()) return it->second;
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), brdf, std::move(params), 1);
  const MerlSynthResult table = tabulateMerl(gpuContext(), gpuCompiler(), analytic, options);
  const auto path = dir.file(name + ".binary");
  writeMerl(path, table.values);
  return made[name] = path;
}

}  // namespace

// Pairs on the hemisphere: uniform ones, and ones whose half vector lies within [thetaMin, thetaMax] of the
// normal, where the square-root theta_h bins are finest.
struct Pairs {
  std::vector<glm::dvec3> wi, wo;
};
Pairs randomPairs(std::size_t count, double thetaMin, double thetaMax, std::uint64_t seed) {
  const auto u = uniformPoints(3 * count, seed);
  Pairs p;
  for (std::size_t i = 0; i + 2 < u.size(); i += 3) {
    const glm::dvec3 o = hemisphere(u[i]);
    glm::dvec3 in = hemisphere(u[i + 1]);
    if (i % 2 == 1) {
      const double thetaH = thetaMin + (thetaMax - thetaMin) * u[i + 1].x, phiH = 2.0 * kPiD * u[i + 1].y;
      const glm::dvec3 h(std::sin(thetaH) * std::cos(phiH), std::sin(thetaH) * std::sin(phiH),
                         std::cos(thetaH));
      in = 2.0 * glm::dot(o, h) * h - o;
    }
    // The GPU receives floats: compare on the same inputs.
    p.wo.push_back(glm::dvec3(glm::vec3(o)));
    p.wi.push_back(glm::dvec3(glm::vec3(in)));
  }
  return p;
}

// Bins of the GPU lookup that differ from the CPU reference lookup, for a table whose values come from
// `value`.
std::size_t lookupMismatches(const std::function<double(int h, int d, int p, int c)>& value,
                             const Pairs& pairs, std::size_t& nonZero) {
  ScratchDir dir;
  std::vector<double> values(3 * kMerlBins);
  for (int h = 0; h < kMerlThetaHBins; ++h)
    for (int d = 0; d < kMerlThetaDBins; ++d)
      for (int p = 0; p < kMerlPhiDBins; ++p)
        for (int c = 0; c < 3; ++c) values[c * kMerlBins + merlBinIndex(h, d, p)] = value(h, d, p, c);
  const auto path = dir.file("table.binary");
  writeMerl(path, values);
  const Scene scene = sceneWith(constantEnv(2, 1, 0.0f), path.string(), {}, 1);
  REQUIRE(scene.measured);
  const auto gpu = evaluateBrdf(gpuContext(), gpuCompiler(), scene, pairs.wi, pairs.wo);
  std::size_t mismatches = 0;
  nonZero = 0;
  for (std::size_t i = 0; i < pairs.wi.size(); ++i) {
    const glm::dvec3 cpu = evalMerl(scene.measured->brdf, pairs.wi[i], pairs.wo[i]);
    nonZero += cpu.x > 0.0;
    mismatches += gpu[i] != cpu;
  }
  return mismatches;
}

TEST_CASE("merl: the GPU lookup agrees with the CPU reference lookup at random direction pairs") {
  // Every bin holds a different value, so a wrong index anywhere shows as a mismatch. phi_d is measured from
  // phi_h, which float cannot resolve when theta_h is tiny (the azimuth of a 1e-4 rad half vector): there the
  // bin of phi_d is noise, harmless for isotropic data (every phi_d is the same measurement at theta_h = 0),
  // so these pairs keep theta_h >= 0.01.
  std::size_t nonZero = 0;
  const Pairs pairs = randomPairs(20000, 0.01, 0.05, 21);
  const std::size_t distinct =
      lookupMismatches([](int h, int d, int p,
                          int c) { return double(merlBinIndex(h, d, p) + 1) * (c + 1) / double(kMerlBins); },
                       pairs, nonZero);
  INFO(distinct << " of " << pairs.wi.size() << " pairs differ");
  // Float against double angles may pick the neighbouring bin within rounding of a bin edge: rare.
  CHECK(distinct <= pairs.wi.size() / 500);
  CHECK(nonZero > pairs.wi.size() / 2);

  // The theta_h mapping down to its first bins (which end at 1.9e-4 rad): values that depend on theta_h only.
  const Pairs nearMirror = randomPairs(20000, 1e-5, 0.01, 22);
  const std::size_t thetaH =
      lookupMismatches([](int h, int, int, int c) { return double(h + 1) * (c + 1); }, nearMirror, nonZero);
  INFO(thetaH << " of " << nearMirror.wi.size() << " near-mirror pairs differ in theta_h");
  CHECK(thetaH <= nearMirror.wi.size() / 500);
  checkNoNewValidationErrors();
}

TEST_CASE("merl: a tabulated Lambert under the white furnace gives its albedo, for every method") {
  // 5.5 sigma per pixel, 5e-4 false alarms for the family under normality; the MERL estimators are bounded
  // but skewed, hence 512 samples. Every registry method once: the MERL z-test below renders every
  // combination of techniques.
  const auto path = synthesize("lambert07", "lambert", {{"albedo", "0.7"}});
  checkWhiteFurnace(sceneWith(constantEnv(16, 8, 1.0f), path.string(), {}, 24), 0.7, 8, 5.5,
                    MethodSet::EveryMethod);
}

TEST_CASE("merl: tabulated GGX renders like the analytic GGX within the tabulation error") {
  const std::vector<std::pair<std::string, std::string>> params{{"roughness", "0.3"}, {"metallic", "1"}};
  const auto path = synthesize("ggx03", "ggx", params);
  const Scene analytic = sceneWith(smoothSky(64, 32), "ggx", params, 24);
  const Scene measured = sceneWith(smoothSky(64, 32), path.string(), {}, 24);
  const ReferenceComparison d = compareReferences(analytic, measured);
  INFO("image sums measured / analytic " << d.sumRatio << ", worst pixel relative difference "
                                         << d.worstRelative);
  CHECK(std::abs(d.sumRatio - 1.0) < 0.02);
  CHECK(d.worstRelative < 0.1);
  checkNoNewValidationErrors();
}

TEST_CASE(
    "merl techniques: GPU agrees with the CPU twin; pdf integrates to 1 and chi2 passes, grazing included") {
  const auto glossy = synthesize("ggx01", "ggx", {{"roughness", "0.1"}, {"metallic", "1"}});
  const auto diffuse = synthesize("lambert07", "lambert", {{"albedo", "0.7"}});
  const Scene glossyScene = sceneWith(constantEnv(2, 1, 0.0f), glossy.string(), {}, 1);
  const MerlThetaHSampler thetaH(buildMerlThetaH(glossyScene.measured->brdf));
  const MerlTableSampler table(buildMerlTable(glossyScene.measured->brdf));
  // Away from slice edges (multiples of 90/32 degrees), where float and double may pick different slices.
  const double views[][2] = {{0.0, 0.0}, {40.0, 30.0}, {85.0, 200.0}};
  const int testCount = 2 * 2 * int(std::size(views));
  for (const auto& material : {glossy, diffuse})
    for (const char* technique : {"merl-thetah", "merl-table"})
      for (const auto& view : views) {
        const glm::dvec3 wo = viewAt(view[0], view[1]);
        INFO(technique << " on " << material.filename().string() << ", theta_o = " << view[0]);
        BrdfTechniqueProbe probe(technique, material.string(), {}, wo);
        const auto u = uniformPoints(200000, 5);
        const auto samples = probe.sample(u);
        std::vector<glm::dvec3> directions;
        std::size_t pdfMismatches = 0, twinMismatches = 0;
        for (std::size_t i = 0; i < samples.size(); ++i) {
          const auto& s = samples[i];
          REQUIRE(std::isfinite(s.pdf));
          if (!(s.pdf > 0.0)) continue;
          directions.push_back(s.direction);
          if (std::abs(s.pdf - s.pdfLookup) > 1e-3 * s.pdf) ++pdfMismatches;
          if (material == glossy && i < 20000) {
            const BrdfSample cpu =
                std::string(technique) == "merl-table" ? table.sample(u[i], wo) : thetaH.sample(u[i], wo);
            if (glm::length(cpu.wi - s.direction) > 1e-3 || std::abs(cpu.pdf - s.pdf) > 1e-3 * cpu.pdf)
              ++twinMismatches;
          }
        }
        // sample() and pdf() locate a sample in the same cell except within float rounding of a cell edge,
        // and the azimuth of a half vector within ~1e-4 rad of the normal is that rounding: up to 1 % in
        // practice.
        CHECK(pdfMismatches <= samples.size() / 100);
        CHECK(twinMismatches <= 200);
        checkChi2AgainstPdf(probe, directions, testCount, "merl-technique");
      }
  checkNoNewValidationErrors();
}

TEST_CASE("merl: every method converges to the convolution reference (z-test)") {
  struct Case {
    std::string name;
    EnvImage env;
    std::filesystem::path material;
  };
  const Case cases[] = {
      {"glossy ggx a=0.1/smooth", smoothSky(32, 16),
       synthesize("ggx01", "ggx", {{"roughness", "0.1"}, {"metallic", "1"}})},
      {"lambert with invalid bins/sun+zero", sunAndZeroHalf(32, 16),
       synthesize("lambert-invalid", "lambert", {{"albedo", "0.6"}}, {true, 0.05, 7})},
  };
  const double zBound = 5.5;  // as in render_gpu_test.cpp
  for (const auto& c : cases)
    checkConvergesToReference(sceneWith(c.env, c.material.string(), {}, 24), c.name, zBound);
}

TEST_CASE(
    "merl hard cases: no NaN or Inf with invalid bins, a near-mirror lobe, a 1e6 sun and grazing pixels") {
  // alpha = 0.01 tabulated (its lobe is a few theta_h bins wide), MERL's -1 below the horizon and in 2 % of
  // the bins, under a sun 1e6 times the sky next to an exactly-zero half; the sphere's rim gives grazing
  // views.
  const auto path =
      synthesize("ggx001-invalid", "ggx", {{"roughness", "0.01"}, {"metallic", "1"}}, {true, 0.02, 11});
  const Scene scene = sceneWith(sunAndZeroHalf(32, 16), path.string(), {}, 32);
  REQUIRE(scene.measured->brdf.invalidBins > 0);
  for (const auto& spec : allMethodSpecs(*scene.brdf, "random")) {
    const ResolvedMethod method = resolveMethod(spec, *scene.brdf);
    INFO(method.label());
    Renderer renderer(gpuContext(), gpuCompiler(), scene, method, 5);
    for (int pass = 0; pass < 2; ++pass) renderer.runPass(64);
    CHECK(renderer.nonFiniteSamples() == 0);
    std::size_t nonFinite = 0;
    for (float v : renderer.meanRgb()) nonFinite += !std::isfinite(v);
    CHECK(nonFinite == 0);
  }
  checkNoNewValidationErrors();
}
