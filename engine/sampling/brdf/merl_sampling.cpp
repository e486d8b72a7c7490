// merl-thetah and the half-vector tables (merl-table, brdf-tab): table builders (double accumulation, float
// storage) and the float-exact CPU twins of shaders/brdf_technique/merl_thetah.glsl and
// half_vector_table.glsl.
#include "engine/sampling/brdf/merl_sampling.h"

#include "engine/core/error.h"
#include "engine/sampling/float_cdf.h"
#include "engine/io/latlong_texel.h"
#include "engine/core/sphere_mapping.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <utility>

namespace iblx {
namespace {

constexpr double kHalfPi = 0.5 * kPi;
constexpr double kTwoPi = 2.0 * kPi;
// Grid intervals per cell axis of the merl-table weights (kTableSubPoints + 1 points, edges included).
constexpr int kTableSubPoints = 4;

// Throws when `brdf` is not a full material with finite, non-negative values (loadMerl guarantees both; an
// in-memory material may not).
void checkMaterial(const MerlBrdf& brdf, const std::string& builder) {
  if (brdf.rgb.size() != 3 * kMerlBins)
    throw Error(builder + ": the material has " + std::to_string(brdf.rgb.size()) + " values, expected 3 x " +
                std::to_string(kMerlBins));
  for (std::size_t i = 0; i < brdf.rgb.size(); ++i) {
    if (!std::isfinite(brdf.rgb[i]) || brdf.rgb[i] < 0.0f)
      throw Error(builder + ": bin " + std::to_string(i % kMerlBins) + " channel " +
                  std::to_string(i / kMerlBins) +
                  " is negative or not finite; load materials with loadMerl, which zeroes invalid bins");
  }
}

// Raises every weight to kMerlFloor * mean weight, so that no bin where the material may reflect gets zero
// (or, after float rounding, zero-width) probability. All-zero weights stay zero (writeFloatCdf makes them
// uniform).
void applyFloor(std::span<double> weights) {
  double total = 0.0;
  for (double w : weights) total += w;
  const double floor = kMerlFloor * total / double(weights.size());
  if (!(floor > 0.0)) return;
  for (double& w : weights) w = std::max(w, floor);
}

// Half vector at (theta_h, phi_h) about the normal +z.
glm::dvec3 halfVector(double thetaH, double phiH) {
  const double s = std::sin(thetaH);
  return {s * std::cos(phiH), s * std::sin(phiH), std::cos(thetaH)};
}

// Mirror of wo about h: wi = 2 (wo.h) h - wo.
glm::dvec3 reflectAbout(glm::dvec3 wo, glm::dvec3 h) {
  return 2.0 * glm::dot(wo, h) * h - wo;
}

// The sqrt-warped theta_h parameter of a half vector: u_theta = sqrt(theta_h / (pi/2)).
struct HalfVectorParams {
  glm::dvec3 h{0.0, 0.0, 1.0};
  double thetaH = 0.0, uTheta = 0.0;
};
// h is flipped into the upper hemisphere, the only one the techniques sample (see merl_sampling.h).
// Empty when wi = -wo.
std::optional<HalfVectorParams> halfVectorParams(glm::dvec3 wi, glm::dvec3 wo) {
  HalfVectorParams p;
  const glm::dvec3 sum = wi + wo;
  const double length = glm::length(sum);
  if (!(length > 0.0)) return std::nullopt;
  p.h = sum / length;
  if (p.h.z < 0.0) p.h = -p.h;
  p.thetaH = std::acos(std::clamp(p.h.z, -1.0, 1.0));
  p.uTheta = std::sqrt(p.thetaH / kHalfPi);
  return p;
}

// Azimuth of wo, 0 when wo is the normal.
double azimuthOf(glm::dvec3 w) {
  return w.x == 0.0 && w.y == 0.0 ? 0.0 : std::atan2(w.y, w.x);
}

// The sample of u_theta, phi_h and p(u) (float, as the GPU computes it), with its solid-angle pdf (also when
// wi falls below the horizon).
BrdfSample reflectedSample(glm::dvec3 wo, double uTheta, double phiH, float pdfU) {
  BrdfSample s;
  const double thetaH = uTheta * uTheta * kHalfPi;
  const glm::dvec3 h = halfVector(thetaH, phiH);
  s.wi = reflectAbout(wo, h);
  s.pdf = halfVectorPdfToSolidAngle(double(pdfU), uTheta, thetaH, glm::dot(wo, h));
  return s;
}

}  // namespace

double halfVectorPdfToSolidAngle(double pdfU, double uTheta, double thetaH, double woDotH) {
  // p(wi) = p(u) / (2 pi^2 u_theta sin(theta_h) * 4 |wo.h|); Mitsuba 3 measured.cpp, Walter et al. 2007.
  const double jacobian = 2.0 * kPi * kPi * uTheta * std::sin(thetaH);
  if (!(jacobian > 0.0)) return 0.0;
  const double denominator = jacobian * 4.0 * std::abs(woDotH);
  if (!(denominator > 0.0) || !std::isfinite(denominator)) return 0.0;
  return pdfU / denominator;
}

// ---- merl-thetah
// -----------------------------------------------------------------------------------------------

MerlThetaHData buildMerlThetaH(const MerlBrdf& brdf) {
  checkMaterial(brdf, "merl-thetah");
  constexpr std::size_t kBinsPerThetaH = std::size_t(kMerlThetaDBins) * kMerlPhiDBins;
  std::array<double, kMerlThetaHBins> weights{};
  for (int i = 0; i < kMerlThetaHBins; ++i) {
    // Mean sampling weight over the theta_d, phi_d bins of this theta_h ...
    double sum = 0.0;
    const std::size_t first = std::size_t(i) * kBinsPerThetaH;
    for (std::size_t k = first; k < first + kBinsPerThetaH; ++k) sum += merlSamplingWeight(brdf, k);
    // ... times the solid angle of the band [theta_lo, theta_hi), cos(lo) - cos(hi) written without
    // cancellation as 2 sin((hi + lo) / 2) sin((hi - lo) / 2).
    const double lo = double(i) * i / (kMerlThetaHBins * kMerlThetaHBins) * kHalfPi;
    const double hi = double(i + 1) * (i + 1) / (kMerlThetaHBins * kMerlThetaHBins) * kHalfPi;
    const double band = 2.0 * std::sin(0.5 * (hi + lo)) * std::sin(0.5 * (hi - lo));
    weights[std::size_t(i)] = sum / double(kBinsPerThetaH) * band;
  }
  applyFloor(weights);
  MerlThetaHData data;
  data.cdf.resize(kMerlThetaHBins + 1);
  writeFloatCdf(weights, data.cdf.data());
  return data;
}

MerlThetaHSampler::MerlThetaHSampler(MerlThetaHData data) : data_(std::move(data)) {
  if (data_.cdf.size() != std::size_t(kMerlThetaHBins) + 1)
    throw Error("merl-thetah: the CDF has " + std::to_string(data_.cdf.size()) + " entries, expected " +
                std::to_string(kMerlThetaHBins + 1) + "; rebuild it with buildMerlThetaH");
}

BrdfSample MerlThetaHSampler::sample(glm::dvec2 u, glm::dvec3 wo) const {
  if (!(wo.z > 0.0)) return {};
  const float ux = toGpuU(u.x), uy = toGpuU(u.y);
  // theta_h bin i from the CDF, then t = offset of u.x inside it.
  const float* cdf = data_.cdf.data();
  const int i = findFloatBin(cdf, kMerlThetaHBins, ux);
  const float prob = cdf[i + 1] - cdf[i];
  const float t = remapInFloatBin(ux, cdf[i], prob);
  const float pdfU = prob * float(kMerlThetaHBins);
  // u_theta = (i + t) / 90, phi_h = 2 pi u.y uniform.
  const double uTheta = (double(i) + double(t)) / kMerlThetaHBins;
  return reflectedSample(wo, uTheta, kTwoPi * double(uy), pdfU);
}

double MerlThetaHSampler::pdf(glm::dvec3 wi, glm::dvec3 wo) const {
  if (!(wo.z > 0.0)) return 0.0;
  const auto half = halfVectorParams(wi, wo);
  if (!half) return 0.0;
  const HalfVectorParams& p = *half;
  const int i = merlCellIndex(p.uTheta * kMerlThetaHBins, kMerlThetaHBins);
  const float* cdf = data_.cdf.data();
  const float pdfU = (cdf[i + 1] - cdf[i]) * float(kMerlThetaHBins);
  return halfVectorPdfToSolidAngle(double(pdfU), p.uTheta, p.thetaH, glm::dot(wo, p.h));
}

// ---- merl-table
// ------------------------------------------------------------------------------------------------

MerlTableData buildHalfVectorTable(const HalfVectorSliceWeights& weights,
                                   const HalfVectorTableOptions& options) {
  const int azimuths = options.absolutePhi ? options.viewAzimuths : 1;
  if (azimuths < 1) throw Error("buildHalfVectorTable: at least one view azimuth is needed");
  constexpr int kRows = kMerlTableThetaBins, kCols = kMerlTablePhiBins, kSub = kTableSubPoints;
  // The grid points, shared by all slices: kSub + 1 per cell and axis, edges included (neighbouring cells
  // share their edge points), all shifted by kMerlTableGridOffset of a grid step so that none lies on a MERL
  // bin edge or in wo's plane of incidence, where the bin would depend on rounding. Per row point theta_h
  // with its sine, cosine and Jacobian factor 2 pi^2 u_theta sin(theta_h); per column point (cos, sin) of
  // phi_h = 2 pi u_phi (phi_o = 0 for the slice's edges).
  constexpr int kRowPoints = kRows * kSub + 1, kColumnPoints = kCols * kSub + 1;
  struct RowPoint {
    double thetaH, sinThetaH, cosThetaH, jacobian;
  };
  std::vector<RowPoint> rowPoints(kRowPoints);
  for (int a = 0; a < kRowPoints; ++a) {
    const double uTheta = (a + kMerlTableGridOffset) / (kRows * kSub);
    const double thetaH = uTheta * uTheta * kHalfPi;
    rowPoints[std::size_t(a)] = {thetaH, std::sin(thetaH), std::cos(thetaH),
                                 2.0 * kPi * kPi * uTheta * std::sin(thetaH)};
  }
  std::vector<glm::dvec2> columnPoints(kColumnPoints);
  for (int b = 0; b < kColumnPoints; ++b) {
    const double phiH = kTwoPi * (b + kMerlTableGridOffset) / (kCols * kSub);
    columnPoints[std::size_t(b)] = {std::cos(phiH), std::sin(phiH)};
  }

  MerlTableData data;
  data.absolutePhi = options.absolutePhi;
  data.tables.resize(std::size_t(kMerlTableSlices) * kMerlTableSliceFloats);
  std::vector<double> cells(std::size_t(kRows) * kCols), rowWeights(kRows);
  std::vector<double> points(std::size_t(kRowPoints) * kColumnPoints);
  std::vector<HalfVectorTablePoint> queries;
  std::vector<std::size_t> queryPoint;  // the grid point of each query
  std::vector<double> queryFactor, queryWeight;
  for (int s = 0; s < kMerlTableSlices; ++s) {
    // The slice serves every wo with theta_o in [lo, hi): its weights are the larger of the two edges' (see
    // merl_sampling.h), so no wo in it finds its lobe in cells the table starves, at the horizon above all.
    const double edges[2] = {(s + kMerlTableEdgeInset) / kMerlTableSlices * kHalfPi,
                             (s + 1 - kMerlTableEdgeInset) / kMerlTableSlices * kHalfPi};
    const glm::dvec3 wos[2] = {{std::sin(edges[0]), 0.0, std::cos(edges[0])},
                               {std::sin(edges[1]), 0.0, std::cos(edges[1])}};
    // g(u) = w(f(wi, wo)) cos(theta_i) 2 pi^2 u_theta sin(theta_h) 4 |wo.h| at every grid point, the larger
    // of the two edges': p(u) proportional to g makes p(wi) proportional to w(f) cos(theta_i). The pairs
    // with wi above the horizon go to `weights` in one batch per slice.
    queries.clear();
    queryPoint.clear();
    queryFactor.clear();
    // absolutePhi: the same (u_theta, u_phi) with the view rotated about the normal to each azimuth, h fixed
    // (u_phi is h's own azimuth); the largest weight is kept (see merl_sampling.h).
    for (int k = 0; k < azimuths; ++k) {
      const double phiO = kTwoPi * k / azimuths;
      const glm::dvec2 rot(std::cos(phiO), std::sin(phiO));
      const auto rotate = [&](glm::dvec3 v) {
        return glm::dvec3(rot.x * v.x - rot.y * v.y, rot.y * v.x + rot.x * v.y, v.z);
      };
      for (int a = 0; a < kRowPoints; ++a) {
        const RowPoint& rp = rowPoints[std::size_t(a)];
        for (int b = 0; b < kColumnPoints; ++b) {
          const glm::dvec2 cs =
              columnPoints[std::size_t(b)];  // phi_h (relative to phi_o = 0 unless absolute)
          const glm::dvec3 h(rp.sinThetaH * cs.x, rp.sinThetaH * cs.y, rp.cosThetaH);
          for (const glm::dvec3& edge : wos) {
            const glm::dvec3 wo = rotate(edge);
            const double woDotH = glm::dot(wo, h);
            const glm::dvec3 wi = 2.0 * woDotH * h - wo;
            if (!(wi.z > 0.0) || !(rp.jacobian > 0.0)) continue;  // f = 0 and cos clamps to 0, or no area
            queries.push_back({wi, wo, rp.thetaH, rp.sinThetaH, rp.cosThetaH, cs});
            queryPoint.push_back(std::size_t(a) * kColumnPoints + std::size_t(b));
            queryFactor.push_back(wi.z * rp.jacobian * 4.0 * std::abs(woDotH));
          }
        }
      }
    }
    queryWeight.assign(queries.size(), 0.0);
    weights(queries, queryWeight);
    std::fill(points.begin(), points.end(), 0.0);
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const double w = queryWeight[q];
      if (!(w > 0.0) || !std::isfinite(w)) continue;  // a negative or non-finite value reflects nothing
      points[queryPoint[q]] = std::max(points[queryPoint[q]], w * queryFactor[q]);
    }
    // Cell weight: the largest g on the cell's (kSub + 1)^2 points, a conservative envelope.
    for (int r = 0; r < kRows; ++r)
      for (int c = 0; c < kCols; ++c) {
        double cellMax = 0.0;
        for (int a = r * kSub; a <= (r + 1) * kSub; ++a)
          for (int b = c * kSub; b <= (c + 1) * kSub; ++b)
            cellMax = std::max(cellMax, points[std::size_t(a) * kColumnPoints + std::size_t(b)]);
        cells[std::size_t(r * kCols + c)] = cellMax;
      }
    applyFloor(cells);
    // And at kMerlFloor * each row's mean, so a row holding most of the slice keeps every cell's width above
    // float spacing in its conditional CDF (the slice floor alone can fall below 2^-24 of such a row).
    for (int r = 0; r < kRows; ++r) applyFloor(std::span(cells).subspan(std::size_t(r) * kCols, kCols));

    // Marginal over rows from the row sums, then one conditional per row.
    float* slice = data.tables.data() + std::size_t(s) * kMerlTableSliceFloats;
    for (int r = 0; r < kRows; ++r) {
      const std::span<const double> row(cells.data() + std::size_t(r) * kCols, std::size_t(kCols));
      double sum = 0.0;
      for (double w : row) sum += w;
      rowWeights[std::size_t(r)] = sum;
      writeFloatCdf(row, slice + (kRows + 1) + std::size_t(r) * (kCols + 1));
    }
    writeFloatCdf(rowWeights, slice);
  }
  return data;
}

MerlTableData buildMerlTable(const MerlBrdf& brdf) {
  checkMaterial(brdf, "merl-table");
  // Sampling weight w = mean of R, G, B of every MERL bin, read once per query below.
  std::vector<double> binWeights(kMerlBins);
  for (std::size_t i = 0; i < kMerlBins; ++i) binWeights[i] = merlSamplingWeight(brdf, i);
  return buildHalfVectorTable([&](std::span<const HalfVectorTablePoint> queries, std::span<double> out) {
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const HalfVectorTablePoint& p = queries[q];
      // f = evalMerl(brdf, wi, wo), with the half vector and its angles known: wi in the frame of h (rotated
      // by -phi_h about z, then by -theta_h about y, as merlAngles does) gives theta_d and phi_d.
      const glm::dvec3& wi = p.wi;
      const double x1 = wi.x * p.phiH.x + wi.y * p.phiH.y, y1 = wi.y * p.phiH.x - wi.x * p.phiH.y;
      MerlAngles angles;
      angles.thetaH = p.thetaH;
      angles.thetaD = std::acos(std::clamp(x1 * p.sinThetaH + wi.z * p.cosThetaH, -1.0, 1.0));
      angles.phiD = std::atan2(y1, x1 * p.cosThetaH - wi.z * p.sinThetaH);
      if (angles.phiD < 0.0) angles.phiD += kPi;
      if (angles.phiD >= kPi) angles.phiD = 0.0;
      const glm::ivec3 bin = merlBin(angles);
      out[q] = binWeights[merlBinIndex(bin.x, bin.y, bin.z)];
    }
  });
}

MerlTableSampler::MerlTableSampler(MerlTableData data) : data_(std::move(data)) {
  if (data_.tables.size() != std::size_t(kMerlTableSlices) * kMerlTableSliceFloats)
    throw Error("merl-table: the tables have " + std::to_string(data_.tables.size()) + " floats, expected " +
                std::to_string(std::size_t(kMerlTableSlices) * kMerlTableSliceFloats) +
                "; rebuild them with buildMerlTable");
}

int MerlTableSampler::sliceOf(glm::dvec3 wo) {
  const double thetaO = std::acos(std::clamp(wo.z, -1.0, 1.0));
  return merlCellIndex(thetaO / kHalfPi * kMerlTableSlices, kMerlTableSlices);
}

BrdfSample MerlTableSampler::sample(glm::dvec2 u, glm::dvec3 wo) const {
  if (!(wo.z > 0.0)) return {};
  constexpr int kRows = kMerlTableThetaBins, kCols = kMerlTablePhiBins;
  const float ux = toGpuU(u.x), uy = toGpuU(u.y);
  const float* marginal = data_.tables.data() + std::size_t(sliceOf(wo)) * kMerlTableSliceFloats;
  // Row i (u_theta) from the slice's marginal with u.y, then column j (u_phi) from row i's conditional with
  // u.x.
  const int i = findFloatBin(marginal, kRows, uy);
  const float rowProb = marginal[i + 1] - marginal[i];
  const float ty = remapInFloatBin(uy, marginal[i], rowProb);
  const float* conditional = marginal + (kRows + 1) + std::size_t(i) * (kCols + 1);
  const int j = findFloatBin(conditional, kCols, ux);
  const float colProb = conditional[j + 1] - conditional[j];
  const float tx = remapInFloatBin(ux, conditional[j], colProb);
  const float pdfU = rowProb * colProb * float(kRows) * float(kCols);
  // u_theta = (i + t.y) / rows; phi_h = phi_o + 2 pi (j + t.x) / columns.
  const double uTheta = (double(i) + double(ty)) / kRows;
  const double phiH = (data_.absolutePhi ? 0.0 : azimuthOf(wo)) + kTwoPi * (double(j) + double(tx)) / kCols;
  return reflectedSample(wo, uTheta, phiH, pdfU);
}

double MerlTableSampler::pdf(glm::dvec3 wi, glm::dvec3 wo) const {
  if (!(wo.z > 0.0)) return 0.0;
  constexpr int kRows = kMerlTableThetaBins, kCols = kMerlTablePhiBins;
  const auto half = halfVectorParams(wi, wo);
  if (!half) return 0.0;
  const HalfVectorParams& p = *half;
  // u_phi = fract((phi_h - phi_o) / (2 pi)); h = +z has no azimuth, and any column gives it pdf 0 anyway.
  const double turns = (std::atan2(p.h.y, p.h.x) - (data_.absolutePhi ? 0.0 : azimuthOf(wo))) / kTwoPi;
  const double uPhi = turns - std::floor(turns);
  const int i = merlCellIndex(p.uTheta * kRows, kRows), j = merlCellIndex(uPhi * kCols, kCols);
  const float* marginal = data_.tables.data() + std::size_t(sliceOf(wo)) * kMerlTableSliceFloats;
  const float* conditional = marginal + (kRows + 1) + std::size_t(i) * (kCols + 1);
  const float rowProb = marginal[i + 1] - marginal[i], colProb = conditional[j + 1] - conditional[j];
  const float pdfU = rowProb * colProb * float(kRows) * float(kCols);
  return halfVectorPdfToSolidAngle(double(pdfU), p.uTheta, p.thetaH, glm::dot(wo, p.h));
}

TechniqueData merlBrdfTechniqueData(const MerlBrdf& brdf) {
  TechniqueData data;
  data.add("merlRgb", brdf.rgb);
  return data;
}

TechniqueData merlThetaHTechniqueData(const MerlThetaHData& table) {
  TechniqueData data;
  data.add("merlThetaHCdf", table.cdf);
  return data;
}

TechniqueData halfVectorTableTechniqueData(const MerlTableData& table) {
  TechniqueData data;
  data.add("merlTable", table.tables);
  if (table.absolutePhi) data.define("HALF_VECTOR_TABLE_ABSOLUTE_PHI", "1");
  return data;
}

}  // namespace iblx
