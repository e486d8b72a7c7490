// Tests of merl-thetah and merl-table (engine/sampling/brdf/merl_sampling.h) on materials tabulated at the
// MERL bin centres from analytic functions: table invariants, weights against the header's recipe, sample/pdf
// agreement, sample -> invert round trips, chi-square against the twins' own densities, normalisation (pdf
// integral = kept fraction), the horizon, and the variance gain of merl-table over merl-thetah.
#include "engine/sampling/brdf/merl_sampling.h"

#include "engine/core/error.h"
#include "engine/io/latlong_texel.h"
#include "engine/core/sphere_mapping.h"
#include "tests/support/chi2.h"

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

using namespace iblx;

namespace {

constexpr double kHalfPi = 0.5 * kPi;
constexpr double kDegree = kPi / 180.0;

// A material whose bin (i, j, k) holds f at the bin's centre angles, tinted per channel (sampling weighs the
// mean of R, G and B).
template <typename F>
MerlBrdf tabulate(F f) {
  constexpr double kTint[3] = {1.0, 0.8, 0.6};
  MerlBrdf brdf;
  brdf.rgb.resize(3 * kMerlBins);
  for (int i = 0; i < kMerlThetaHBins; ++i) {
    const double u = (i + 0.5) / kMerlThetaHBins, thetaH = u * u * kHalfPi;
    for (int j = 0; j < kMerlThetaDBins; ++j) {
      const double thetaD = (j + 0.5) / kMerlThetaDBins * kHalfPi;
      for (int k = 0; k < kMerlPhiDBins; ++k) {
        const double phiD = (k + 0.5) / kMerlPhiDBins * kPi, v = f(thetaH, thetaD, phiD);
        const std::size_t bin = merlBinIndex(i, j, k);
        for (int c = 0; c < 3; ++c) brdf.rgb[std::size_t(c) * kMerlBins + bin] = float(v * kTint[c]);
      }
    }
  }
  return brdf;
}

// GGX normal distribution D(theta_h) = alpha^2 / (pi (alpha^2 cos^2 + sin^2)^2) (Walter et al. 2007), written
// without tan so it stays finite at theta_h = pi/2.
double ggxD(double thetaH, double alpha) {
  const double c = std::cos(thetaH), s = std::sin(thetaH), a2 = alpha * alpha, d = a2 * c * c + s * s;
  return a2 / (kPi * d * d);
}

// A glossy lobe: D times a Schlick-like Fresnel in theta_d and a mild phi_d term (smooth, positive).
MerlBrdf glossyMaterial(double alpha) {
  return tabulate([alpha](double thetaH, double thetaD, double phiD) {
    const double fresnel = 0.04 + 0.96 * std::pow(1.0 - std::cos(thetaD), 5.0);
    return ggxD(thetaH, alpha) * fresnel * (1.0 + 0.2 * std::cos(phiD)) / 4.0;
  });
}

struct Material {
  std::string name;
  MerlBrdf brdf;
  MerlThetaHSampler thetaH;
  MerlTableSampler table;
  double thetaHBuildMs = 0.0, tableBuildMs = 0.0;  // wall time of the two builders (Release: < 1 s)
};

Material makeMaterial(std::string name, MerlBrdf brdf) {
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  const auto start = Clock::now();
  MerlThetaHData thetaH = buildMerlThetaH(brdf);
  const auto middle = Clock::now();
  MerlTableData table = buildMerlTable(brdf);
  const auto end = Clock::now();
  return {std::move(name),
          std::move(brdf),
          MerlThetaHSampler(std::move(thetaH)),
          MerlTableSampler(std::move(table)),
          ms(middle - start),
          ms(end - middle)};
}

// Built once: the table builder is the slow part of this file.
const std::vector<Material>& materials() {
  static const std::vector<Material> all = [] {
    std::vector<Material> m;
    m.push_back(makeMaterial("lambert", tabulate([](double, double, double) { return 1.0 / kPi; })));
    m.push_back(makeMaterial("ggx-0.3", glossyMaterial(0.3)));
    m.push_back(makeMaterial("ggx-0.05", glossyMaterial(0.05)));
    return m;
  }();
  return all;
}

const Material& material(const std::string& name) {
  for (const Material& m : materials())
    if (m.name == name) return m;
  throw Error("no test material " + name);
}

// wo at theta_o, with azimuth 40 degrees so that merl-table's rotation by phi_o is exercised.
glm::dvec3 outgoing(double thetaODegrees) {
  const double t = thetaODegrees * kDegree, p = 40.0 * kDegree;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

constexpr double kThetaOs[] = {0.0, 30.0, 60.0, 85.0};
// The chi-square family: 2 techniques x 3 materials x 4 theta_o (Sidak correction over all of them).
constexpr int kChi2Family = 2 * 3 * 4;
constexpr std::size_t kChi2Samples = 30000;

// Both techniques through one interface.
struct Technique {
  const char* name;
  BrdfSample (*sample)(const Material&, glm::dvec2, glm::dvec3);
  double (*pdf)(const Material&, glm::dvec3, glm::dvec3);
};
const Technique kThetaH{"merl-thetah",
                        [](const Material& m, glm::dvec2 u, glm::dvec3 wo) { return m.thetaH.sample(u, wo); },
                        [](const Material& m, glm::dvec3 wi, glm::dvec3 wo) { return m.thetaH.pdf(wi, wo); }};
const Technique kTable{"merl-table",
                       [](const Material& m, glm::dvec2 u, glm::dvec3 wo) { return m.table.sample(u, wo); },
                       [](const Material& m, glm::dvec3 wi, glm::dvec3 wo) { return m.table.pdf(wi, wo); }};

// (a) chi-square and (b) normalisation of one technique for one material, at every theta_o.
//
// A sample with pdf 0 is dropped (a degenerate Jacobian, which happens with probability 0; samples below the
// horizon keep their true density, so q should be 1): it is not a direction, so the histogram holds only
// the K kept samples of N draws. The sampler's pdf is a sub-probability density whose integral q over the
// sphere is the probability of keeping a sample. Conditional on K, the kept samples are K independent draws
// from pdf / q, so (a) compares them with pdf / q: an exact chi-square test of the shape, with q the
// harness's own integral of the pdf (a first pass), so that the expected counts sum to K, the one constraint
// behind the harness's degrees of freedom. Dividing by the observed K / N instead gives expected counts N p_c
// that sum to N q, not K; that statistic is the N-draw statistic without its "dropped" term and is
// distributed as chi2(C - 1) + (1 - q) chi2(1), slightly more than the harness assumes. The information in K
// is tested by (b) instead: K / N estimates q with binomial standard deviation sqrt(q (1 - q) / N).
//
// maxRefineDepth 4 keeps a pass at 20 to 80 ms; the integral is then within 5e-4 of the depth-10 one on these
// materials (the steep alpha = 0.05 lobe is the worst), which the tolerance of (b) allows for.
void checkChi2AndNormalisation(const Technique& technique, const Material& m, std::uint64_t seed) {
  for (double thetaO : kThetaOs) {
    const glm::dvec3 wo = outgoing(thetaO);
    const std::string label = std::string(technique.name) + "-" + m.name + "-" + std::to_string(int(thetaO));
    CAPTURE(label);
    std::vector<glm::dvec3> kept;
    kept.reserve(kChi2Samples);
    int badPdf = 0;
    for (const glm::dvec2 u : test::uniformPoints(kChi2Samples, seed++)) {
      const BrdfSample s = technique.sample(m, u, wo);
      badPdf += !(std::isfinite(s.pdf) && s.pdf >= 0.0);
      if (s.pdf > 0.0) kept.push_back(s.wi);
    }
    REQUIRE(badPdf == 0);
    REQUIRE(!kept.empty());
    const double keptFraction = double(kept.size()) / double(kChi2Samples);

    test::Chi2Options options;
    options.label = label;
    options.testCount = kChi2Family;
    options.maxRefineDepth = 4;
    double scale = 1.0;
    const test::BatchPdf pdf = [&](std::span<const glm::dvec3> ws) {
      std::vector<double> p(ws.size());
      for (std::size_t k = 0; k < ws.size(); ++k) p[k] = technique.pdf(m, ws[k], wo) * scale;
      return p;
    };
    const double q = test::chi2Test(kept, pdf, options).pdfIntegral;
    REQUIRE(q > 0.0);
    scale = 1.0 / q;
    const test::Chi2Result r = test::chi2Test(kept, pdf, options);
    INFO(r.message);
    CHECK(r.passed);

    // (b) 5 binomial standard deviations (q may exceed 1 by the integration error), plus 1e-3 for that error.
    const double qClamped = std::min(q, 1.0);
    const double sigma = std::sqrt(qClamped * (1.0 - qClamped) / double(kChi2Samples));
    INFO("pdf integral " << q << ", kept fraction " << keptFraction << ", sigma " << sigma);
    CHECK(std::abs(q - keptFraction) <= 5.0 * sigma + 1e-3);
  }
}

// (c) sample(u).pdf == pdf(sample(u).wi) and (d) the horizon. The two compute the same float p(u) (the same
// cell) and the Jacobian in double from u_theta and h, recomputed from wi in pdf(); only a sample within
// rounding of a cell edge may be located in the neighbouring cell.
void checkPdfAgreesWithSample(const Technique& technique, const Material& m) {
  for (double thetaO : kThetaOs) {
    const glm::dvec3 wo = outgoing(thetaO);
    CAPTURE(thetaO);
    int kept = 0, notUnitAbove = 0, edge = 0;
    for (const glm::dvec2 u : test::uniformPoints(20000, 300 + std::uint64_t(thetaO))) {
      const BrdfSample s = technique.sample(m, u, wo);
      if (!(s.pdf > 0.0)) continue;
      ++kept;
      notUnitAbove += !(std::abs(glm::length(s.wi) - 1.0) < 1e-12);
      const double p = technique.pdf(m, s.wi, wo);
      edge += !(std::abs(p - s.pdf) <= 1e-4 * s.pdf);
    }
    // Every sample keeps its density, below the horizon too (shaders/interfaces/brdf_technique.glsl).
    CHECK(kept > 19900);
    CHECK(notUnitAbove == 0);
    CHECK(edge <= 1);
    // For wo below the horizon, and for wi = -wo, the density is 0.
    int nonZero = 0;
    for (const glm::dvec2 u : test::uniformPoints(2000, 400 + std::uint64_t(thetaO))) {
      const double z = -u.x, r = std::sqrt(1.0 - z * z), phi = 2.0 * kPi * u.y;
      const glm::dvec3 below(r * std::cos(phi), r * std::sin(phi), z);
      nonZero += technique.pdf(m, wo, below) != 0.0;
      nonZero += technique.sample(m, u, below).pdf != 0.0;
    }
    CHECK(nonZero == 0);
    CHECK(technique.pdf(m, -wo, wo) == 0.0);
  }
}

// The inverses of the two warps, derived here from the header's definitions (the samplers have none): from
// h = normalize(wi + wo), u_theta = sqrt(theta_h / (pi/2)) and u_phi = phi_h / (2 pi) (merl-thetah) or
// fract((phi_h - phi_o) / (2 pi)) (merl-table); then u = cdf[bin] + (offset inside the bin) * P per axis.
// They catch a wrong warp inside a bin, which neither the pdf comparison nor a chi-square test at the
// harness's resolution (cells much wider than a MERL theta_h bin) can see.
struct HalfAngles {
  double uTheta = 0.0, phiH = 0.0;
};
HalfAngles halfAngles(glm::dvec3 wi, glm::dvec3 wo) {
  glm::dvec3 h = glm::normalize(wi + wo);
  if (h.z < 0.0) h = -h;  // the sampled half vector is in the upper hemisphere
  return {std::sqrt(std::acos(std::clamp(h.z, -1.0, 1.0)) / kHalfPi), std::atan2(h.y, h.x)};
}
double fract(double x) {
  return x - std::floor(x);
}
// u in a CDF over n bins for a position x in [0, n).
double cdfInverse(const float* cdf, int n, double x) {
  const int k = std::clamp(int(x), 0, n - 1);
  return double(cdf[k]) + (x - k) * double(cdf[k + 1] - cdf[k]);
}
glm::dvec2 invertThetaH(const MerlThetaHData& d, glm::dvec3 wi, glm::dvec3 wo) {
  const HalfAngles a = halfAngles(wi, wo);
  return {cdfInverse(d.cdf.data(), kMerlThetaHBins, a.uTheta * kMerlThetaHBins), fract(a.phiH / (2.0 * kPi))};
}
glm::dvec2 invertTable(const MerlTableData& d, glm::dvec3 wi, glm::dvec3 wo) {
  constexpr int kRows = kMerlTableThetaBins, kCols = kMerlTablePhiBins;
  const HalfAngles a = halfAngles(wi, wo);
  const double phiO = wo.x == 0.0 && wo.y == 0.0 ? 0.0 : std::atan2(wo.y, wo.x);
  const float* marginal =
      d.tables.data() + std::size_t(MerlTableSampler::sliceOf(wo)) * kMerlTableSliceFloats;
  const double row = a.uTheta * kRows;
  const float* conditional = marginal + kRows + 1 + std::clamp(int(row), 0, kRows - 1) * (kCols + 1);
  return {cdfInverse(conditional, kCols, fract((a.phiH - phiO) / (2.0 * kPi)) * kCols),
          cdfInverse(marginal, kRows, row)};
}

// (c') sample -> invert round trip: the u that produced wi comes back, up to float rounding (the twin's u is
// toGpuU(u)) and the wrap of phi. A sample within rounding of a row edge of merl-table may be inverted in the
// neighbouring row, whose conditional differs.
template <typename Invert>
void checkRoundTrip(const Technique& technique, const Material& m, Invert invert) {
  for (double thetaO : kThetaOs) {
    const glm::dvec3 wo = outgoing(thetaO);
    CAPTURE(thetaO);
    int kept = 0, wrong = 0;
    double worst = 0.0;
    for (const glm::dvec2 u : test::uniformPoints(20000, 500 + std::uint64_t(thetaO))) {
      const BrdfSample s = technique.sample(m, u, wo);
      if (!(s.pdf > 0.0)) continue;
      ++kept;
      const glm::dvec2 back = invert(m, s.wi, wo);
      const glm::dvec2 gpuU(toGpuU(u.x), toGpuU(u.y));
      // Distance on the torus: u_phi wraps around.
      const glm::dvec2 d = glm::abs(back - gpuU);
      const double e = std::max(std::min(d.x, 1.0 - d.x), std::min(d.y, 1.0 - d.y));
      if (e > 1e-6)
        ++wrong;
      else
        worst = std::max(worst, e);
    }
    INFO("worst error of the others " << worst);
    CHECK(kept > 5000);
    CHECK(wrong <= 1);
  }
}

// A CDF as every builder must write it: n + 1 entries, [0] = 0, [n] = 1, non-decreasing; with the floor,
// every bin has positive width.
void checkCdf(const float* cdf, int n) {
  CHECK(cdf[0] == 0.0f);
  CHECK(cdf[n] == 1.0f);
  int zeroWidth = 0;
  for (int k = 0; k < n; ++k) zeroWidth += !(cdf[k + 1] > cdf[k]);
  CHECK(zeroWidth == 0);
}

}  // namespace

TEST_CASE("merl-thetah: tables on the test materials and the Lambert weights by hand") {
  for (const Material& m : materials()) {
    CAPTURE(m.name);
    REQUIRE(m.thetaH.data().cdf.size() == std::size_t(kMerlThetaHBins) + 1);
    checkCdf(m.thetaH.data().cdf.data(), kMerlThetaHBins);
  }
  // Lambert: every bin has the same mean weight, so bin i gets the solid angle of its band, floored at 1e-4
  // of the mean band (the first bins are tiny: bin 0 spans theta_h < 0.011 degrees).
  std::vector<double> band(kMerlThetaHBins);
  double total = 0.0;
  for (int i = 0; i < kMerlThetaHBins; ++i) {
    const double lo = std::pow(i / 90.0, 2) * kHalfPi, hi = std::pow((i + 1) / 90.0, 2) * kHalfPi;
    band[std::size_t(i)] = std::cos(lo) - std::cos(hi);
    total += band[std::size_t(i)];
  }
  const double floor = kMerlFloor * total / kMerlThetaHBins;
  double floored = 0.0;
  for (double& b : band) floored += (b = std::max(b, floor));
  CHECK(band[0] == floor);  // the floor is active
  const std::vector<float>& cdf = material("lambert").thetaH.data().cdf;
  for (int i = 0; i < kMerlThetaHBins; ++i) {
    CAPTURE(i);
    CHECK(double(cdf[std::size_t(i) + 1] - cdf[std::size_t(i)]) ==
          doctest::Approx(band[std::size_t(i)] / floored).epsilon(1e-5).scale(0.0));
  }
}

TEST_CASE("merl-table: tables on the test materials") {
  for (const Material& m : materials()) {
    CAPTURE(m.name);
    const std::vector<float>& t = m.table.data().tables;
    REQUIRE(t.size() == std::size_t(kMerlTableSlices) * kMerlTableSliceFloats);
    for (int s = 0; s < kMerlTableSlices; ++s) {
      CAPTURE(s);
      const float* marginal = t.data() + std::size_t(s) * kMerlTableSliceFloats;
      checkCdf(marginal, kMerlTableThetaBins);
      for (int r = 0; r < kMerlTableThetaBins; ++r)
        checkCdf(marginal + kMerlTableThetaBins + 1 + r * (kMerlTablePhiBins + 1), kMerlTablePhiBins);
    }
  }
  // Slices: theta_o uniform over [0, pi/2], 32 of them, the last one closed.
  CHECK(MerlTableSampler::sliceOf({0.0, 0.0, 1.0}) == 0);
  CHECK(MerlTableSampler::sliceOf(outgoing(30.0)) == 10);
  CHECK(MerlTableSampler::sliceOf(outgoing(85.0)) == 30);
  CHECK(MerlTableSampler::sliceOf({1.0, 0.0, 0.0}) == kMerlTableSlices - 1);
}

TEST_CASE("merl-table: cell probabilities follow the documented weights") {
  // The header's recipe, written out with evalMerl: cell weight = maximum over a 5 x 5 grid (edges included)
  // of g(u) = max over the slice's two edges wo_e of w(f(wi, wo_e)) max(wi.z, 0) 2 pi^2 u_theta sin(theta_h)
  // 4 |wo_e.h|, floored at 1e-4 of the slice's
  // mean, then at 1e-4 of the row's mean; row probability = row sum / total, column probability = cell / row
  // sum. The float tables may differ from these by the rounding of two CDF entries.
  constexpr int kRows = kMerlTableThetaBins, kCols = kMerlTablePhiBins;
  for (const Material& m : materials()) {
    CAPTURE(m.name);
    for (int s : {0, 13, 30}) {
      CAPTURE(s);
      const double lo = (s + kMerlTableEdgeInset) / kMerlTableSlices * kHalfPi,
                   hi = (s + 1 - kMerlTableEdgeInset) / kMerlTableSlices * kHalfPi;
      const glm::dvec3 edges[2] = {{std::sin(lo), 0.0, std::cos(lo)}, {std::sin(hi), 0.0, std::cos(hi)}};
      std::vector<double> cells(std::size_t(kRows) * kCols, 0.0);
      for (int r = 0; r < kRows; ++r)
        for (int c = 0; c < kCols; ++c)
          for (int a = 0; a <= 4; ++a)
            for (int b = 0; b <= 4; ++b) {
              const double uTheta = (r + (a + kMerlTableGridOffset) / 4.0) / kRows,
                           uPhi = (c + (b + kMerlTableGridOffset) / 4.0) / kCols;
              const double thetaH = uTheta * uTheta * kHalfPi, phiH = 2.0 * kPi * uPhi;
              const glm::dvec3 h(std::sin(thetaH) * std::cos(phiH), std::sin(thetaH) * std::sin(phiH),
                                 std::cos(thetaH));
              double g = 0.0;
              for (const glm::dvec3& wo : edges) {
                const glm::dvec3 wi = 2.0 * glm::dot(wo, h) * h - wo;
                const glm::dvec3 f = evalMerl(m.brdf, wi, wo);
                g = std::max(g, (f.x + f.y + f.z) / 3.0 * std::max(wi.z, 0.0) * 2.0 * kPi * kPi * uTheta *
                                    std::sin(thetaH) * 4.0 * std::abs(glm::dot(wo, h)));
              }
              double& cell = cells[std::size_t(r * kCols + c)];
              cell = std::max(cell, g);
            }
      double total = 0.0;
      for (double w : cells) total += w;
      for (double& w : cells) w = std::max(w, kMerlFloor * total / double(cells.size()));
      for (int r = 0; r < kRows; ++r) {  // then at kMerlFloor of the row's mean
        double rowSum = 0.0;
        for (int c = 0; c < kCols; ++c) rowSum += cells[std::size_t(r * kCols + c)];
        for (int c = 0; c < kCols; ++c)
          cells[std::size_t(r * kCols + c)] =
              std::max(cells[std::size_t(r * kCols + c)], kMerlFloor * rowSum / kCols);
      }
      std::vector<double> rows(kRows, 0.0);
      total = 0.0;
      for (int r = 0; r < kRows; ++r) {
        for (int c = 0; c < kCols; ++c) rows[std::size_t(r)] += cells[std::size_t(r * kCols + c)];
        total += rows[std::size_t(r)];
      }
      const float* marginal = m.table.data().tables.data() + std::size_t(s) * kMerlTableSliceFloats;
      double worstRow = 0.0, worstColumn = 0.0;
      for (int r = 0; r < kRows; ++r) {
        const double p = double(marginal[r + 1] - marginal[r]);
        worstRow = std::max(worstRow, std::abs(p - rows[std::size_t(r)] / total));
        const float* conditional = marginal + kRows + 1 + r * (kCols + 1);
        for (int c = 0; c < kCols; ++c) {
          const double q = double(conditional[c + 1] - conditional[c]);
          worstColumn =
              std::max(worstColumn, std::abs(q - cells[std::size_t(r * kCols + c)] / rows[std::size_t(r)]));
        }
      }
      CHECK(worstRow < 2e-7);
      CHECK(worstColumn < 2e-7);
    }
  }
}

TEST_CASE("merl-thetah and merl-table: an all-zero material samples u uniformly") {
  MerlBrdf black;
  black.rgb.assign(3 * kMerlBins, 0.0f);
  const MerlThetaHData thetaHData = buildMerlThetaH(black);
  for (int i = 0; i <= kMerlThetaHBins; ++i)
    CHECK(thetaHData.cdf[std::size_t(i)] == doctest::Approx(double(i) / kMerlThetaHBins).epsilon(1e-6));
  const MerlTableData table = buildMerlTable(black);
  for (int s = 0; s < kMerlTableSlices; s += 7) {
    const float* marginal = table.tables.data() + std::size_t(s) * kMerlTableSliceFloats;
    for (int r = 0; r <= kMerlTableThetaBins; ++r)
      CHECK(marginal[r] == doctest::Approx(double(r) / kMerlTableThetaBins).epsilon(1e-6));
    const float* conditional = marginal + kMerlTableThetaBins + 1 + 45 * (kMerlTablePhiBins + 1);
    for (int c = 0; c <= kMerlTablePhiBins; ++c)
      CHECK(conditional[c] == doctest::Approx(double(c) / kMerlTablePhiBins).epsilon(1e-6));
  }
  // p(u) = 1 everywhere: the density is the bare Jacobian 1 / (2 pi^2 u_theta sin(theta_h) 4 wo.h).
  const MerlTableSampler sampler{table};
  const BrdfSample s = sampler.sample({0.3, 0.6}, {0.0, 0.0, 1.0});
  const double uTheta = 0.6, thetaH = uTheta * uTheta * kHalfPi;
  CHECK(s.pdf ==
        doctest::Approx(1.0 / (2.0 * kPi * kPi * uTheta * std::sin(thetaH) * 4.0 * std::cos(thetaH))));
  // phi_h = 2 pi 0.3 and wi = reflect(n, h).
  const glm::dvec3 h(std::sin(thetaH) * std::cos(0.6 * kPi), std::sin(thetaH) * std::sin(0.6 * kPi),
                     std::cos(thetaH));
  CHECK(glm::length(s.wi - (2.0 * h.z * h - glm::dvec3(0.0, 0.0, 1.0))) < 1e-6);
}

TEST_CASE("merl-thetah and merl-table: reject bad input") {
  MerlBrdf empty;
  CHECK_THROWS_AS(buildMerlThetaH(empty), Error);
  CHECK_THROWS_AS(buildMerlTable(empty), Error);
  MerlBrdf negative;
  negative.rgb.assign(3 * kMerlBins, 1.0f);
  negative.rgb[12345] = -1.0f;
  CHECK_THROWS_AS(buildMerlThetaH(negative), Error);
  CHECK_THROWS_AS(buildMerlTable(negative), Error);
  CHECK_THROWS_AS(MerlThetaHSampler(MerlThetaHData{std::vector<float>(10)}), Error);
  CHECK_THROWS_AS(MerlTableSampler(MerlTableData{std::vector<float>(10)}), Error);
}

TEST_CASE("merl: halfVectorPdfToSolidAngle") {
  // p(wi) = p(u) / (2 pi^2 u_theta sin(theta_h) 4 |wo.h|).
  CHECK(halfVectorPdfToSolidAngle(2.0, 0.5, 0.3, 0.7) ==
        doctest::Approx(2.0 / (2.0 * kPi * kPi * 0.5 * std::sin(0.3) * 4.0 * 0.7)));
  CHECK(halfVectorPdfToSolidAngle(1.0, 0.0, 0.0, 1.0) == 0.0);
  CHECK(halfVectorPdfToSolidAngle(1.0, 0.5, 0.3, 0.0) == 0.0);
  // |wo.h|: the density of a reflection below the horizon (sampled h with wo.h < 0).
  CHECK(halfVectorPdfToSolidAngle(1.0, 0.5, 0.3, -0.2) == halfVectorPdfToSolidAngle(1.0, 0.5, 0.3, 0.2));
  CHECK(halfVectorPdfToSolidAngle(1.0, 1e-300, 1e-300, 1e-300) == 0.0);  // underflow
}

TEST_CASE("merl-thetah: chi2 and normalisation") {
  std::uint64_t seed = 1000;
  for (const Material& m : materials()) checkChi2AndNormalisation(kThetaH, m, (seed += 100));
}

TEST_CASE("merl-table: chi2 and normalisation") {
  std::uint64_t seed = 2000;
  for (const Material& m : materials()) checkChi2AndNormalisation(kTable, m, (seed += 100));
}

TEST_CASE("merl-thetah: pdf agrees with sample; 0 below the horizon") {
  for (const Material& m : materials()) {
    CAPTURE(m.name);
    checkPdfAgreesWithSample(kThetaH, m);
  }
}

TEST_CASE("merl-table: pdf agrees with sample; 0 below the horizon") {
  for (const Material& m : materials()) {
    CAPTURE(m.name);
    checkPdfAgreesWithSample(kTable, m);
  }
}

TEST_CASE("merl-thetah: sample -> invert round trip") {
  for (const Material& m : materials()) {
    CAPTURE(m.name);
    checkRoundTrip(kThetaH, m, [](const Material& mm, glm::dvec3 wi, glm::dvec3 wo) {
      return invertThetaH(mm.thetaH.data(), wi, wo);
    });
  }
}

TEST_CASE("merl-table: sample -> invert round trip") {
  for (const Material& m : materials()) {
    CAPTURE(m.name);
    checkRoundTrip(kTable, m, [](const Material& mm, glm::dvec3 wi, glm::dvec3 wo) {
      return invertTable(mm.table.data(), wi, wo);
    });
  }
}

TEST_CASE("merl-table: lower variance than merl-thetah on a glossy lobe; same integral") {
  // Estimator of the integral of w(f) cos(theta_i) over the hemisphere: w(f(wi, wo)) wi.z / pdf, 0 for a
  // dropped sample (the pdf is positive wherever f cos is, so both are unbiased for the same integral).
  const Material& m = material("ggx-0.05");
  const glm::dvec3 wo = outgoing(30.0);
  constexpr std::size_t kSamples = 20000;
  struct Estimate {
    double mean = 0.0, variance = 0.0;
  };
  const auto estimate = [&](const Technique& technique) {
    double sum = 0.0, sumSquares = 0.0;
    for (const glm::dvec2 u : test::uniformPoints(kSamples, 77)) {
      const BrdfSample s = technique.sample(m, u, wo);
      if (!(s.pdf > 0.0)) continue;
      const glm::dvec3 f = evalMerl(m.brdf, s.wi, wo);
      const double y = (f.x + f.y + f.z) / 3.0 * s.wi.z / s.pdf;
      sum += y;
      sumSquares += y * y;
    }
    Estimate e;
    e.mean = sum / kSamples;
    e.variance = (sumSquares - sum * e.mean) / (kSamples - 1);
    return e;
  };
  const Estimate thetaH = estimate(kThetaH), table = estimate(kTable);
  INFO("merl-thetah: mean " << thetaH.mean << ", variance " << thetaH.variance << "; merl-table: mean "
                            << table.mean << ", variance " << table.variance);
  CHECK(table.variance < 0.25 * thetaH.variance);
  const double standardError = std::sqrt((thetaH.variance + table.variance) / kSamples);
  CHECK(std::abs(thetaH.mean - table.mean) < 5.0 * standardError);
  MESSAGE("merl-thetah variance " << thetaH.variance << ", merl-table variance " << table.variance
                                  << ", integral " << table.mean);
}

TEST_CASE("merl-thetah and merl-table: build time of a material") {
  // Reported, not checked (timings depend on the machine and its load); the tables are built by materials().
  for (const Material& m : materials())
    MESSAGE(m.name << ": buildMerlThetaH " << m.thetaHBuildMs << " ms, buildMerlTable " << m.tableBuildMs
                   << " ms");
}

TEST_CASE("merl-table: no wo of a grazing slice finds its lobe starved") {
  // Regression: built for the slice's centre alone, the table gave floor-level probability to the part of a
  // grazing lobe that reflects below the horizon at the centre but above it for a less grazing wo of the same
  // slice; f cos / pdf reached thousands of times the albedo there, and renders under a sun were dominated by
  // those samples. The weight w(f) cos / pdf of any direction must stay within a small factor of the albedo:
  // measured, at most 2 times with the maximum over the cell and the edges' envelope; 25 times with the mean
  // over the cell (thin slivers of the horizon crossing a cell); 700 to 2000 times with the slice's centre
  // alone.
  const Material& m = materials()[2];  // GGX alpha = 0.05
  REQUIRE(m.name == "ggx-0.05");
  const double sliceDegrees = 90.0 / kMerlTableSlices;
  for (int s : {24, 28, 30, 31})
    for (double at : {0.02, 0.5, 0.98}) {
      const double thetaO = (s + at) * sliceDegrees;
      const glm::dvec3 wo = outgoing(thetaO);
      CAPTURE(thetaO);
      // Directions spread over the lobe and beyond it: merl-thetah's samples.
      double worst = 0.0, albedo = 0.0;
      int count = 0;
      for (const glm::dvec2 u : test::uniformPoints(20000, 700 + std::uint64_t(s))) {
        const BrdfSample probe = m.thetaH.sample(u, wo);
        if (!(probe.pdf > 0.0) || !(probe.wi.z > 0.0)) continue;
        const glm::dvec3 f = evalMerl(m.brdf, probe.wi, wo);
        const double value = (f.x + f.y + f.z) / 3.0 * probe.wi.z;
        albedo += value / probe.pdf;
        ++count;
        const double pdf = m.table.pdf(probe.wi, wo);
        if (value > 0.0) worst = std::max(worst, pdf > 0.0 ? value / pdf : 1e30);
      }
      albedo /= 20000.0;
      INFO("albedo " << albedo << ", worst w(f) cos / pdf " << worst << " over " << count << " directions");
      REQUIRE(albedo > 0.0);
      CHECK(worst < 5.0 * albedo);
    }
}
