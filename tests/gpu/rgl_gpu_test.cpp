// RGL-EPFL .bsdf materials on the GPU, with files written by the project's own tabulation (tabulateRgl):
// evaluation and the rgl-vndf technique against their CPU twins (engine/sampling/brdf/rgl_sampling.h),
// chi-square of rgl-vndf against its pdf, the white furnace of a tabulated Lambert, tabulated against
// analytic GGX, the tangent frame of an anisotropic material, and every method against the reference under a
// 1e6 sun.
#include "engine/core/assets.h"
#include "engine/io/rgl_bsdf.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/sampling/brdf/rgl_sampling.h"
#include "tests/gpu/gpu_fixture.h"
#include "tests/gpu/render_checks.h"
#include "tests/io/scratch_files.h"
#include "tests/support/chi2.h"
#include "tests/support/hard_envs.h"

#include <doctest/doctest.h>

#include <map>

using namespace iblx;
using namespace iblx::test;

namespace {

// Tabulated once per test run into a scratch directory that lives as long as the process.
std::filesystem::path synthesizeRgl(const std::string& name, const std::string& brdf,
                                    std::vector<std::pair<std::string, std::string>> params,
                                    std::uint32_t phiViews = 1) {
  static ScratchDir dir;
  static std::map<std::string, std::filesystem::path> made;
  if (auto it = made.find(name); it != made.end()) return it->second;
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), brdf, std::move(params), 1);
  RglSynthLayout layout;
  layout.alpha = 0.0;  // from the lobe
  layout.phiViews = phiViews;
  const auto path = dir.file(name + ".bsdf");
  writeRglBsdf(path, tabulateRgl(gpuContext(), gpuCompiler(), analytic, layout));
  return made[name] = path;
}

}  // namespace

TEST_CASE("rgl: the GPU evaluation and rgl-vndf agree with their CPU twins, isotropic and anisotropic") {
  const std::string ward = assetPath("brdf/ward.brdf").string();
  for (const auto& [path, views] : {std::pair{synthesizeRgl("ggx", "ggx", {{"roughness", "0.3"}}), 1u},
                                    std::pair{synthesizeRgl("ward", ward, {}, 17), 17u}}) {
    CAPTURE(path.filename().string());
    const RglBsdf cpu(loadRglBsdf(path));
    REQUIRE(cpu.isotropic() == (views == 1));
    const auto u = uniformPoints(2 * 4000, 51);
    std::vector<glm::dvec3> wi, wo;
    for (std::size_t i = 0; i + 1 < u.size(); i += 2) {
      wi.push_back(glm::dvec3(glm::vec3(hemisphere(u[i]))));  // the GPU receives floats
      wo.push_back(glm::dvec3(glm::vec3(hemisphere(u[i + 1]))));
    }
    const Scene scene = sceneWith(constantEnv(2, 1, 0.0f), path.string(), {}, 1);
    const auto gpu = evaluateBrdf(gpuContext(), gpuCompiler(), scene, wi, wo);
    // f cos, which the file stores (f alone divides float rounding by a grazing light's cosine).
    double worst = 0.0, largest = 0.0;
    for (std::size_t i = 0; i < wi.size(); ++i)
      largest = std::max(largest, cpu.eval(wi[i], wo[i]).g * wi[i].z);
    for (std::size_t i = 0; i < wi.size(); ++i) {
      const glm::dvec3 f = cpu.eval(wi[i], wo[i]);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(gpu[i][c] - f[c]) * wi[i].z / (f[c] * wi[i].z + 1e-3 * largest));
    }
    INFO("worst relative difference " << worst);
    CHECK(worst < 0.02);  // float CDFs and angles against double ones: measured 1 %

    for (const double thetaO : {20.0, 70.0}) {
      const glm::dvec3 view = viewAt(thetaO, 35.0);
      BrdfTechniqueProbe probe("rgl-vndf", path.string(), {}, view);
      const auto points = uniformPoints(2000, 61);
      const auto samples = probe.sample(points);
      std::size_t far = 0;
      for (std::size_t k = 0; k < points.size(); ++k) {
        const RglBsdf::Sample s = cpu.sample(points[k], glm::dvec3(glm::vec3(view)));
        REQUIRE(s.pdf > 0.0);
        const bool near =
            glm::length(samples[k].direction - s.wi) < 3e-3 && std::abs(samples[k].pdf / s.pdf - 1.0) < 1e-2;
        far += !near;
      }
      INFO(far << " of " << points.size() << " samples differ at theta_o = " << thetaO);
      // Float CDFs and angles against double ones: measured within 1.6e-3 rad and 0.1 % of the pdf.
      CHECK(far <= points.size() / 200);
    }
  }
  checkNoNewValidationErrors();
}

TEST_CASE("rgl: rgl-vndf passes chi-square against its pdf, grazing included") {
  const auto path = synthesizeRgl("ggx", "ggx", {{"roughness", "0.3"}});
  const double views[][2] = {{0.0, 0.0}, {45.0, 100.0}, {85.0, 250.0}};
  for (const auto& view : views) {
    INFO("theta_o = " << view[0]);
    BrdfTechniqueProbe probe("rgl-vndf", path.string(), {}, viewAt(view[0], view[1]));
    const auto samples = probe.sample(uniformPoints(100000, 9));
    std::vector<glm::dvec3> directions;
    for (const auto& s : samples)
      if (s.pdf > 0.0) directions.push_back(s.direction);
    checkChi2AgainstPdf(probe, directions, int(std::size(views)), "rgl-vndf");
  }
  checkNoNewValidationErrors();
}

TEST_CASE("rgl: a tabulated Lambert under the white furnace gives its albedo") {
  // The format interpolates f cos 4 sigma / ndf bilinearly over the warp's unit square, which a Lambert does
  // not follow exactly (it has a kink where the light crosses the horizon): the tabulated material's ground
  // truth is compared with the analytic Lambert's, its albedo. Every method meets the ground truth of an RGL
  // material in the 1e6-sun test below.
  const auto path = synthesizeRgl("lambert07", "lambert", {{"albedo", "0.7"}});
  const ReferenceComparison d =
      compareReferences(sceneWith(constantEnv(16, 8, 1.0f), "lambert", {{"albedo", "0.7"}}, 24),
                        sceneWith(constantEnv(16, 8, 1.0f), path.string(), {}, 24));
  INFO("image sums measured / analytic " << d.sumRatio << ", worst pixel relative difference "
                                         << d.worstRelative);
  CHECK(std::abs(d.sumRatio - 1.0) < 0.01);
  CHECK(d.worstRelative < 0.03);
}

TEST_CASE("rgl: tabulated GGX renders like the analytic GGX within the tabulation error") {
  const std::vector<std::pair<std::string, std::string>> params{{"roughness", "0.3"}, {"metallic", "1"}};
  const auto path = synthesizeRgl("ggx03", "ggx", params);
  const Scene analytic = sceneWith(smoothSky(64, 32), "ggx", params, 24);
  const Scene measured = sceneWith(smoothSky(64, 32), path.string(), {}, 24);
  const ReferenceComparison d = compareReferences(analytic, measured);
  INFO("image sums measured / analytic " << d.sumRatio << ", worst pixel relative difference "
                                         << d.worstRelative);
  CHECK(std::abs(d.sumRatio - 1.0) < 0.01);
  CHECK(d.worstRelative < 0.1);
  checkNoNewValidationErrors();
}

TEST_CASE("rgl: a tabulated anisotropic material follows the tangent frame") {
  const std::string ward = assetPath("brdf/ward.brdf").string();
  const auto path = synthesizeRgl("ward", ward, {}, 17);
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), ward, {}, 1);
  const Scene measured = sceneWith(constantEnv(2, 1, 0.0f), path.string(), {}, 1);
  // A view at 45 degrees and a light at 30 degrees opposite, then both turned by 90 degrees about the normal:
  // Ward's alphaX 0.15 x alphaY 0.4 lobe falls off faster along the tangent.
  const std::vector<glm::dvec3> wis{viewAt(30.0, 180.0), viewAt(30.0, 270.0)};
  const std::vector<glm::dvec3> wos{viewAt(45.0, 0.0), viewAt(45.0, 90.0)};
  const auto f = evaluateBrdf(gpuContext(), gpuCompiler(), analytic, wis, wos);
  const auto g = evaluateBrdf(gpuContext(), gpuCompiler(), measured, wis, wos);
  INFO("Ward " << f[0].x << " / " << f[1].x << ", tabulated " << g[0].x << " / " << g[1].x);
  CHECK(std::abs(f[1].x / f[0].x - 1.0) > 0.3);  // the analytic lobe is anisotropic
  for (int k = 0; k < 2; ++k) CHECK(g[k].x == doctest::Approx(f[k].x).epsilon(0.05));
  CHECK(g[1].x / g[0].x == doctest::Approx(f[1].x / f[0].x).epsilon(0.05));
  checkNoNewValidationErrors();
}

TEST_CASE("rgl: every method converges to the reference under a 1e6 sun") {
  const std::string ward = assetPath("brdf/ward.brdf").string();
  checkConvergesToReference(
      sceneWith(sunAndZeroHalf(32, 16), synthesizeRgl("ward", ward, {}, 17).string(), {}, 16),
      "rgl ward/sun+zero", 5.5, MethodSet::EveryMethod);
}
