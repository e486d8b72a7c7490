// ALTA data files on the GPU, written by the project's own tabulation (tabulateAltaData) in every
// parametrisation iblx reads, as text and as binary streams: the kernel's lookup against the CPU twin
// (evalAltaGrid), the white furnace of a tabulated Lambert, a tabulated GGX against the analytic one, the
// tangent frame of an anisotropic material, and every method against the reference under a 1e6 sun.
#include "engine/core/assets.h"
#include "engine/io/alta_data.h"
#include "engine/render/brdf_tabulation.h"
#include "engine/sampling/brdf/alta_grid.h"
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

std::filesystem::path synthesizeAlta(const std::string& name, const std::string& brdf,
                                     std::vector<std::pair<std::string, std::string>> params, AltaParam param,
                                     AltaOutput output = AltaOutput::RgbColor, std::size_t scattered = 0,
                                     bool binary = false) {
  static ScratchDir dir;
  static std::map<std::string, std::filesystem::path> made;
  if (auto it = made.find(name); it != made.end()) return it->second;
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), brdf, std::move(params), 1);
  const auto path = dir.file(name + ".data");
  writeAltaData(path, tabulateAltaData(gpuContext(), gpuCompiler(), analytic, param, output, scattered),
                binary);
  return made[name] = path;
}

constexpr AltaParam kGridParams[] = {AltaParam::RusinThTdPd, AltaParam::RusinThTd,
                                     AltaParam::IsotropicTvTlDphi, AltaParam::SphericalTlPlTvPv};

}  // namespace

TEST_CASE("alta data: the GPU lookup agrees with the CPU twin in every parametrisation, resampled too") {
  const auto u = uniformPoints(2 * 3000, 71);
  std::vector<glm::dvec3> wi, wo;
  for (std::size_t i = 0; i + 1 < u.size(); i += 2) {
    wi.push_back(glm::dvec3(glm::vec3(hemisphere(u[i]))));
    wo.push_back(glm::dvec3(glm::vec3(hemisphere(u[i + 1]))));
  }
  const std::string ward = assetPath("brdf/ward.brdf").string();
  std::vector<std::filesystem::path> files;
  for (AltaParam p : kGridParams) files.push_back(synthesizeAlta("ward-" + altaParamName(p), ward, {}, p));
  files.push_back(
      synthesizeAlta("ward-cartesian", ward, {}, AltaParam::Cartesian, AltaOutput::RgbColor, 3000));
  // Tabulated in their own coordinates (a vector, a 2D and a 1D form): lib/alta_params.glsl's maps.
  for (AltaParam p : {AltaParam::RusinVh, AltaParam::Neumann2d, AltaParam::CosTlr})
    files.push_back(synthesizeAlta("ward-" + altaParamName(p), ward, {}, p, AltaOutput::RgbColor, 3000));
  files.push_back(synthesizeAlta("ggx-rusin-cos-binary", "ggx", {}, AltaParam::RusinThTdPd,
                                 AltaOutput::InvSteradianCosine, 0, true));
  for (const auto& path : files) {
    CAPTURE(path.filename().string());
    WarningCapture quiet;  // the scattered files' resampling warnings
    const AltaGrid grid = makeAltaGrid(loadAltaData(path), path.string());
    const Scene scene = sceneWith(constantEnv(2, 1, 0.0f), path.string(), {}, 1);
    REQUIRE(scene.brdf->evalPart == "brdf/alta_data.glsl");
    const auto gpu = evaluateBrdf(gpuContext(), gpuCompiler(), scene, wi, wo);
    double worst = 0.0, largest = 0.0;
    std::vector<glm::dvec3> cpu;
    for (std::size_t i = 0; i < wi.size(); ++i) cpu.push_back(evalAltaGrid(grid, wi[i], wo[i]) * wi[i].z);
    for (const glm::dvec3& c : cpu) largest = std::max(largest, c.g);
    for (std::size_t i = 0; i < wi.size(); ++i)
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(gpu[i][c] * wi[i].z - cpu[i][c]) / (cpu[i][c] + 1e-3 * largest));
    INFO("worst relative difference of f cos " << worst);
    CHECK(worst < 0.02);  // float angles against double ones where the grid is steep: measured 0.8 %
  }
  checkNoNewValidationErrors();
}

TEST_CASE("alta data: a tabulated Lambert under the white furnace gives its albedo") {
  // A constant table: the ground truth is the analytic Lambert's, its albedo, up to the reference's
  // quadrature. Every method meets the ground truth of an ALTA data file in the 1e6-sun test below.
  const auto path = synthesizeAlta("lambert07", "lambert", {{"albedo", "0.7"}}, AltaParam::IsotropicTvTlDphi,
                                   AltaOutput::InvSteradian);
  const ReferenceComparison d =
      compareReferences(sceneWith(constantEnv(16, 8, 1.0f), "lambert", {{"albedo", "0.7"}}, 24),
                        sceneWith(constantEnv(16, 8, 1.0f), path.string(), {}, 24));
  INFO("image sums measured / analytic " << d.sumRatio << ", worst pixel relative difference "
                                         << d.worstRelative);
  CHECK(std::abs(d.sumRatio - 1.0) < 1e-3);
  CHECK(d.worstRelative < 1e-3);
}

TEST_CASE("alta data: tabulated GGX renders like the analytic GGX within the tabulation error") {
  const std::vector<std::pair<std::string, std::string>> params{{"roughness", "0.5"}, {"metallic", "1"}};
  const Scene analytic = sceneWith(smoothSky(64, 32), "ggx", params, 24);
  struct Case {
    AltaParam param;
    std::size_t scattered;
    double sumTolerance, worstTolerance;
  };
  // Measured: see the INFO lines; the bounds leave room above them.
  const Case cases[] = {{AltaParam::RusinThTdPd, 0, 0.03, 0.3},
                        {AltaParam::IsotropicTvTlDphi, 0, 0.03, 0.3},
                        {AltaParam::SphericalTlPlTvPv, 0, 0.03, 0.3},
                        {AltaParam::Cartesian, 20000, 0.05, 0.5}};
  for (const Case& c : cases) {
    const auto path = synthesizeAlta("ggx05-" + altaParamName(c.param), "ggx", params, c.param,
                                     AltaOutput::RgbColor, c.scattered);
    WarningCapture quiet;
    const Scene measured = sceneWith(smoothSky(64, 32), path.string(), {}, 24);
    const ReferenceComparison d = compareReferences(analytic, measured);
    INFO(altaParamName(c.param) << ": image sums measured / analytic " << d.sumRatio
                                << ", worst pixel relative difference " << d.worstRelative);
    CHECK(std::abs(d.sumRatio - 1.0) < c.sumTolerance);
    CHECK(d.worstRelative < c.worstTolerance);
  }
  checkNoNewValidationErrors();
}

TEST_CASE("alta data: a tabulated anisotropic material follows the tangent frame") {
  const std::string ward = assetPath("brdf/ward.brdf").string();
  const auto path = synthesizeAlta("ward-" + altaParamName(AltaParam::SphericalTlPlTvPv), ward, {},
                                   AltaParam::SphericalTlPlTvPv);
  const Scene analytic = sceneWith(constantEnv(2, 1, 0.0f), ward, {}, 1);
  const Scene measured = sceneWith(constantEnv(2, 1, 0.0f), path.string(), {}, 1);
  // Grid nodes of planAltaSynth's 12 x 24 x 12 x 24 grid (theta every 89 / 11 degrees, phi every 360 / 23
  // from -180): a view at node 7 and a light at node 2 nearly opposite, then both turned by 6 azimuth nodes
  // (94 degrees), so the half vector leans towards the tangent, then towards the bitangent.
  const auto node = [](int theta, int phi) {
    return viewAt(theta * 89.0 / 11.0, -180.0 + phi * 360.0 / 23.0);
  };
  const std::vector<glm::dvec3> wis{node(2, 11), node(2, 17)}, wos{node(7, 0), node(7, 6)};
  const auto f = evaluateBrdf(gpuContext(), gpuCompiler(), analytic, wis, wos);
  const auto g = evaluateBrdf(gpuContext(), gpuCompiler(), measured, wis, wos);
  INFO("Ward " << f[0].x << " / " << f[1].x << ", tabulated " << g[0].x << " / " << g[1].x);
  CHECK(std::abs(f[1].x / f[0].x - 1.0) > 0.3);  // the analytic lobe is anisotropic
  for (int k = 0; k < 2; ++k) CHECK(g[k].x == doctest::Approx(f[k].x).epsilon(0.01));  // grid nodes
  CHECK(g[1].x / g[0].x == doctest::Approx(f[1].x / f[0].x).epsilon(0.02));
  checkNoNewValidationErrors();
}

TEST_CASE("alta data: every method converges to the reference under a 1e6 sun") {
  // The ISOTROPIC_TV_TL_DPHI grid of the Ward (8 corners per lookup; the anisotropic grid's 16 cost twice the
  // time in the reference and every method, and its lookup is checked against the CPU twin above).
  const std::string ward = assetPath("brdf/ward.brdf").string();
  checkConvergesToReference(sceneWith(sunAndZeroHalf(32, 16),
                                      synthesizeAlta("ward-" + altaParamName(AltaParam::IsotropicTvTlDphi),
                                                     ward, {}, AltaParam::IsotropicTvTlDphi)
                                          .string(),
                                      {}, 16),
                            "alta ward/sun+zero", 5.5, MethodSet::EveryMethod);
}
