// Tests of ALTA data on a grid (engine/sampling/brdf/alta_grid.h): regular grids found as they are (uneven
// axes included) and reproduced at their nodes, scattered samples resampled with a warning, the coordinates
// of each parametrisation, and the symmetry folds of azimuths.
#include "engine/sampling/brdf/alta_grid.h"

#include "tests/io/scratch_files.h"
#include "tests/support/chi2.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>

using namespace iblx;
using namespace iblx::test;

namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// A smooth reciprocal, isotropic test function of the pair, per channel.
glm::dvec3 smooth(glm::dvec3 wi, glm::dvec3 wo) {
  const glm::dvec3 h = glm::normalize(wi + wo);
  return glm::dvec3(1.0 + h.z, 1.0 + wi.z * wo.z, 2.0 - glm::dot(wi, wo)) * 0.2;
}

AltaData synthesize(AltaParam param, std::size_t scattered) {
  AltaSynthPlan plan = planAltaSynth(param, AltaOutput::RgbColor, scattered);
  std::vector<glm::dvec3> f;
  for (std::size_t i = 0; i < plan.wi.size(); ++i) f.push_back(smooth(plan.wi[i], plan.wo[i]));
  return finishAltaSynth(std::move(plan), f);
}

}  // namespace

TEST_CASE("alta grid: the writer's grids are found as grids and reproduce the function") {
  for (AltaParam param :
       {AltaParam::RusinThTdPd, AltaParam::IsotropicTvTlDphi, AltaParam::SphericalTlPlTvPv}) {
    CAPTURE(altaParamName(param));
    WarningCapture warnings;
    const AltaGrid grid = makeAltaGrid(synthesize(param, 0), "test");
    CHECK(warnings.messages.empty());
    CHECK(grid.resampledFrom == 0);
    CHECK(grid.axes.size() == std::size_t(altaParamDimension(param)));
    double worst = 0.0;
    for (const glm::dvec2 u : uniformPoints(500, 3)) {
      const glm::dvec3 wi = direction(std::acos(0.2 + 0.8 * u.x), 6.0 * u.y);
      const glm::dvec3 wo = direction(std::acos(0.2 + 0.8 * u.y), 1.0 + 4.0 * u.x);
      const glm::dvec3 f = evalAltaGrid(grid, wi, wo), g = smooth(wi, wo);
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(f[c] / g[c] - 1.0));
    }
    INFO("worst relative error " << worst);
    CHECK(worst < 0.03);  // multilinear interpolation of a smooth function on 12 to 24 nodes per axis
    CHECK(evalAltaGrid(grid, direction(0.3, 0.0), direction(1.7, 0.0)) == glm::dvec3(0.0));
  }
}

TEST_CASE("alta grid: RUSIN_TH_TD_PD's theta_h axis is uneven and phi_d folds by reciprocity") {
  const AltaGrid grid = makeAltaGrid(synthesize(AltaParam::RusinThTdPd, 0), "test");
  const auto& thetaH = grid.axes[0];
  CHECK(thetaH[1] - thetaH[0] < 0.1 * (thetaH.back() - thetaH[thetaH.size() - 2]));
  CHECK(grid.folds[2] == AltaFold::Reciprocity);
  // Swapping light and view adds pi to phi_d: the same value after the fold.
  const glm::dvec3 a = direction(0.4, 0.3), b = direction(0.9, 2.1);
  const auto k = altaRawCoordinates(AltaParam::RusinThTdPd, a, b);
  const auto swapped = altaRawCoordinates(AltaParam::RusinThTdPd, b, a);
  CHECK(k[0] == doctest::Approx(swapped[0]));
  CHECK(k[1] == doctest::Approx(swapped[1]));
  CHECK(std::abs(std::remainder(k[2] - swapped[2], 2.0 * kPi)) == doctest::Approx(kPi).epsilon(1e-9));
  CHECK(evalAltaGrid(grid, a, b).x == doctest::Approx(evalAltaGrid(grid, b, a).x).epsilon(1e-6));
}

TEST_CASE("alta grid: scattered and Cartesian samples are resampled, with a warning") {
  for (AltaParam param : {AltaParam::IsotropicTvTlDphi, AltaParam::Cartesian}) {
    CAPTURE(altaParamName(param));
    WarningCapture warnings;
    const AltaGrid grid = makeAltaGrid(synthesize(param, 20000), "m.data");
    REQUIRE(warnings.messages.size() == 1);
    CHECK(contains(warnings.messages[0], "m.data: the 20000 " + altaParamName(param) + " samples"));
    CHECK(contains(warnings.messages[0], "inverse-distance weighting of the 8 nearest samples"));
    CHECK(grid.resampledFrom == 20000);
    CHECK(grid.param == (param == AltaParam::Cartesian ? AltaParam::SphericalTlPlTvPv : param));
    double mean = 0.0;
    const std::size_t pairs = 400;
    for (const glm::dvec2 u : uniformPoints(pairs, 9)) {
      const glm::dvec3 wi = direction(std::acos(0.2 + 0.7 * u.x), 6.0 * u.y);
      const glm::dvec3 wo = direction(std::acos(0.2 + 0.7 * u.y), 1.0 + 4.0 * u.x);
      mean += std::abs(evalAltaGrid(grid, wi, wo).x / smooth(wi, wo).x - 1.0) / double(pairs);
    }
    INFO("mean relative error " << mean);
    CHECK(mean < 0.05);
  }
}

TEST_CASE("alta grid: clustered samples resample in time, repeats count once, and the leave-one-out error") {
  // N - 1 identical rows and one far sample: every node's 8 nearest used to scan the whole cluster
  // (nodes x samples; 100 000 rows ran for minutes). Repeats are now one sample with their mean value.
  AltaData clustered;
  clustered.param = AltaParam::IsotropicTvTlDphi;
  clustered.output = AltaOutput::RgbColor;
  clustered.samples = 200001;
  for (std::size_t i = 0; i + 1 < clustered.samples; ++i) {
    clustered.x.insert(clustered.x.end(), {0.5, 0.5, 1.0});
    clustered.rgb.insert(clustered.rgb.end(), {i % 2 ? 1.0 : 3.0, 1.0, 1.0});
  }
  clustered.x.insert(clustered.x.end(), {1.2, 1.1, 2.0});
  clustered.rgb.insert(clustered.rgb.end(), {0.5, 0.5, 0.5});
  WarningCapture warnings;
  const AltaGrid grid = makeAltaGrid(clustered, "clustered.data");
  CHECK(grid.resampledFrom == 200001);
  CHECK(grid.distinctSamples == 2);
  CHECK_FALSE(grid.leaveOneOutError.has_value());  // 2 distinct samples: nothing to leave out
  // The node at the cluster takes the repeats' mean, 2.
  CHECK(grid.rgb[0] == doctest::Approx(2.0));

  // Smooth data: each sample is predicted from its neighbours to within a few per cent; noise is not.
  const AltaGrid smoothGrid = makeAltaGrid(synthesize(AltaParam::IsotropicTvTlDphi, 20000), "m.data");
  REQUIRE(smoothGrid.leaveOneOutError.has_value());
  CHECK(*smoothGrid.leaveOneOutError < 0.05);
  CHECK(contains(warnings.messages.back(), "(leave-one-out error "));
  AltaData noisy = synthesize(AltaParam::IsotropicTvTlDphi, 20000);
  for (std::size_t i = 0; i < noisy.rgb.size(); ++i) noisy.rgb[i] *= (i * 2654435761u) % 7 == 0 ? 3.0 : 1.0;
  const AltaGrid noisyGrid = makeAltaGrid(noisy, "noisy.data");
  REQUIRE(noisyGrid.leaveOneOutError.has_value());
  CHECK(*noisyGrid.leaveOneOutError > 3.0 * *smoothGrid.leaveOneOutError);
}

TEST_CASE("alta grid: data in every parametrisation reproduce the function they sample") {
  // Each function depends only on what its parametrisation keeps (a 1D or 2D one drops angles, and data in it
  // say the BRDF does not depend on them).
  const auto value = [](AltaParam p, glm::dvec3 wi, glm::dvec3 wo) {
    const glm::dvec3 h = glm::normalize(wi + wo);
    // Schlick 1994's back vector, as ALTA's SCHLICK_VH writes it and (its z) COS_TK.
    const glm::dvec3 k = glm::normalize(glm::dvec3(wi.x - wo.x, wi.y - wo.y, wi.z + wo.z));
    const glm::dvec3 hTilde = 0.5 * (wi + wo), bTilde = 0.5 * (wi - wo);  // Neumann et al. 1999
    switch (p) {
      case AltaParam::RusinVh:
        return glm::dvec3(0.5 + h.z + 0.2 * h.x - 0.1 * h.y);
      case AltaParam::SchlickVk:
        return glm::dvec3(0.5 + k.z + 0.2 * k.x - 0.1 * k.y);
      case AltaParam::CosTk:
        return glm::dvec3(0.2 + k.z * k.z);
      case AltaParam::CosTlv:
        return glm::dvec3(1.2 - 0.5 * glm::dot(wi, wo));
      case AltaParam::CosTlr:  // ALTA's expression (engine/io/alta_params.h)
        return glm::dvec3(1.2 + 0.5 * (wo.x * wi.x - wo.y * wi.y - wo.z * wi.z));
      case AltaParam::Neumann2d:
        return glm::dvec3(0.3 + std::hypot(hTilde.x, hTilde.y) + 0.5 * std::hypot(bTilde.x, bTilde.y));
      case AltaParam::CosTh:
        return glm::dvec3(0.5 + h.z);
      case AltaParam::CosThTd:
      case AltaParam::Stark2d:
        return glm::dvec3(0.5 + h.z + 0.5 * glm::dot(wi, h));
      case AltaParam::IsotropicTvProjDphi: {
        const double dphi = std::atan2(wo.y, wo.x) - std::atan2(wi.y, wi.x);
        return glm::dvec3(1.0 + wo.z + 0.2 * std::cos(dphi));
      }
      default:
        return smooth(wi, wo);
    }
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (AltaParam p : altaParams()) {
    const AltaParam table = altaTableParam(p);
    if (p == AltaParam::Cartesian || altaParamIsTableParam(p))
      continue;  // grids of their own, and Cartesian: tested above
    CAPTURE(altaParamName(p));
    const int dims = altaParamDimension(p);
    AltaData data;
    data.param = p;
    data.output = AltaOutput::RgbColor;
    for (int i = 0; i < 20000; ++i) {
      const glm::dvec3 wi = direction(std::acos(0.05 + 0.95 * u(rng)), 2.0 * kPi * u(rng));
      const glm::dvec3 wo = direction(std::acos(0.05 + 0.95 * u(rng)), 2.0 * kPi * u(rng));
      const auto x = altaRawCoordinates(p, wi, wo);
      data.x.insert(data.x.end(), x.begin(), x.begin() + dims);
      const glm::dvec3 f = value(p, wi, wo);
      data.rgb.insert(data.rgb.end(), {f.x, f.y, f.z});
    }
    data.samples = 20000;
    WarningCapture warnings;
    const AltaGrid grid = makeAltaGrid(data, "m.data");
    CHECK(grid.param == table);
    REQUIRE(warnings.messages.size() == 1);
    if (table != p)
      CHECK(contains(warnings.messages[0], "read as " + altaParamName(table) + " coordinates"));
    else
      CHECK(contains(warnings.messages[0],
                     "the 20000 " + altaParamName(p) + " samples do not lie on a regular grid"));
    double mean = 0.0;
    const std::size_t pairs = 400;
    for (const glm::dvec2 v : uniformPoints(pairs, 9)) {
      const glm::dvec3 wi = direction(std::acos(0.2 + 0.7 * v.x), 6.0 * v.y);
      const glm::dvec3 wo = direction(std::acos(0.2 + 0.7 * v.y), 1.0 + 4.0 * v.x);
      mean += std::abs(evalAltaGrid(grid, wi, wo).x / value(p, wi, wo).x - 1.0) / double(pairs);
    }
    INFO("mean relative error " << mean);
    CHECK(mean < 0.05);
  }
}

TEST_CASE(
    "alta grid: the four table parametrisations tabulate as themselves, every other maps to one or keeps its "
    "own") {
  int tables = 0;
  for (AltaParam p : altaParams()) {
    CAPTURE(altaParamName(p));
    const AltaParam table = altaTableParam(p);
    if (altaParamIsTableParam(p)) {
      ++tables;
      CHECK(table == p);
    } else {
      CHECK((altaParamIsTableParam(table) || table == p));
    }
  }
  CHECK(tables == 4);
  CHECK(altaTableParam(AltaParam::Cartesian) == AltaParam::SphericalTlPlTvPv);
  CHECK(altaTableParam(AltaParam::CosTh) == AltaParam::RusinThTd);
  CHECK(altaTableParam(AltaParam::Stark3d) == AltaParam::IsotropicTvTlDphi);
  CHECK(altaTableParam(AltaParam::RusinVh) == AltaParam::RusinVh);
}
