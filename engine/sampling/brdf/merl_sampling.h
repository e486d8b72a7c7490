// Importance sampling of MERL materials: builders (double) and float-exact CPU twins of the BRDF techniques
// `merl-thetah` (shaders/brdf_technique/merl_thetah.glsl) and `merl-table`
// (shaders/brdf_technique/half_vector_table.glsl, which also serves `brdf-tab` for any BRDF). Both sample a
// half vector h around the normal in the square-root-warped parameterisation of MERL's theta_h,
//   u_theta = sqrt(theta_h / (pi/2)),  u_phi = phi_h / (2 pi),
// and reflect: wi = 2 (wo.h) h - wo. Densities (Mitsuba 3, src/bsdfs/measured.cpp):
//   p(h) = p(u) / (2 pi^2 u_theta sin(theta_h))      [d omega_h = sin theta_h d theta_h d phi_h]
//   p(wi) = p(h) / (4 |wo.h|)                        [Walter et al. 2007, eq. 14]
// Everything runs in the local shading frame: normal +z, wo.z > 0. As for every BRDF technique
// (shaders/interfaces/brdf_technique.glsl), wi may fall below the horizon and its pdf is still the true
// density: pdf() of any wi uses h = normalize(wi + wo) flipped into the upper hemisphere (h.z >= 0; a sampled
// h with wo.h < 0 reflects wo to a wi whose normalize(wi + wo) is -h), so pdf integrates to 1 over the
// sphere.
#pragma once

#include "engine/io/merl.h"
#include "engine/sampling/technique_data.h"

#include <glm/glm.hpp>

#include <functional>
#include <span>
#include <vector>

namespace iblx {

// A sampled direction with its solid-angle density (0 only for a degenerate Jacobian: a sample to drop).
struct BrdfSample {
  glm::dvec3 wi{0.0, 0.0, 1.0};
  double pdf = 0.0;
};

// Solid-angle density of wi given p(u) of the half-vector parameters, with |wo.h|; 0 when the Jacobian is
// not positive or not finite (shared by both techniques and their twins).
double halfVectorPdfToSolidAngle(double pdfU, double uTheta, double thetaH, double woDotH);

// ---- merl-thetah: a 1D distribution over the 90 theta_h bins, phi_h uniform ----
// Bin i weight: (mean over all theta_d, phi_d bins of the bin's sampling
// weight (mean of R, G, B)) times the solid angle of its theta_h band, cos(theta_lo) - cos(theta_hi); then
// floored at kMerlFloor * mean weight so that no bin where the material reflects is ever unreachable (a float
// CDF can round tiny shares to zero width). An all-zero material gives the uniform distribution. CDF in
// double, stored as float, cdf[90] = 1.
inline constexpr double kMerlFloor = 1e-4;
struct MerlThetaHData {
  std::vector<float> cdf;  // kMerlThetaHBins + 1 entries
};
MerlThetaHData buildMerlThetaH(const MerlBrdf& brdf);

// Twin of the GLSL part, in float where the GPU is in float (table reads, bin search, remap):
//   bin i = largest with cdf[i] <= u.x (a zero-width bin is never chosen); t = (u.x - cdf[i]) / P_i clamped
//   to [0, 1 - 2^-24]; u_theta = (i + t) / 90; theta_h = u_theta^2 pi/2; phi_h = 2 pi u.y; p(u) = P_i * 90;
//   wi = reflect; pdf from halfVectorPdfToSolidAngle (also below the horizon).
class MerlThetaHSampler {
 public:
  explicit MerlThetaHSampler(MerlThetaHData data);
  BrdfSample sample(glm::dvec2 u, glm::dvec3 wo) const;
  // Density of wi for wo: 0 when wo.z <= 0 or wi = -wo; else from h (see the top) and its bin.
  double pdf(glm::dvec3 wi, glm::dvec3 wo) const;
  const MerlThetaHData& data() const { return data_; }

 private:
  MerlThetaHData data_;
};

// ---- merl-table: per-theta_o slices of 2D tables over (u_theta, u_phi) ----
// kMerlTableSlices slices uniform in theta_o over [0, pi/2]: wo's
// slice is min(int(theta_o / (pi/2) * S), S - 1), for sample() and pdf() alike. Slice s serves theta_o in
// [lo, hi) = [s, s + 1) / S * pi/2, as a grid of kMerlTableThetaBins (u_theta, matching MERL's theta_h bins)
// x kMerlTablePhiBins (u_phi = phi_h relative to wo's azimuth, over [0, 2 pi)) cells. Cell weight: the
// largest value on a 5 x 5 grid of points spanning the cell, its edges included, of
//   g(u) = max over wo_e in {wo(lo + e), wo(hi - e)} of
//          w(f(wi, wo_e)) max(wi.z, 0) 2 pi^2 u_theta sin(theta_h) 4 |wo_e.h|
// (w = mean of R, G, B; wo(t) = (sin t, 0, cos t); wi the reflection of wo_e; e = kMerlTableEdgeInset slices,
// which keeps wo_e off the normal, where phi_d is undefined, and off the horizon). The envelope of the two
// edges matters at grazing views: part of the lobe that reflects below the horizon for one wo of the slice
// reflects above it for another, and a table built for the slice's centre alone would starve it (f cos / pdf,
// and the variance, would explode there). The maximum over the cell, rather than its mean, does the same
// inside a cell: a lobe or the horizon crossing a cell cannot hide between interior points, so w(f) cos / pdf
// stays bounded. with f the nearest-bin lookup (evalMerl), floored at kMerlFloor * the slice's mean cell
// weight and then at kMerlFloor * its row's mean (every cell stays reachable, whatever wo within the slice,
// and keeps a width above float spacing in its row's CDF). A slice whose weights are all zero is uniform.
// Each slice is a marginal over u_theta rows and one conditional over u_phi per row, in double, stored as
// float.
inline constexpr int kMerlTableSlices = 32, kMerlTableThetaBins = 90, kMerlTablePhiBins = 64;
inline constexpr double kMerlTableEdgeInset = 1e-3;
// The 5 x 5 points of a cell sit at (row + (a + kMerlTableGridOffset) / 4) / ThetaBins and the same in u_phi,
// a = 0..4: off MERL's bin edges, which the rows share, and off the plane of incidence.
inline constexpr double kMerlTableGridOffset = 1e-3;
// Floats per slice: marginal (ThetaBins + 1), then ThetaBins conditionals of (PhiBins + 1).
inline constexpr int kMerlTableSliceFloats =
    (kMerlTableThetaBins + 1) + kMerlTableThetaBins * (kMerlTablePhiBins + 1);
struct MerlTableData {
  std::vector<float> tables;  // kMerlTableSlices * kMerlTableSliceFloats, slice after slice
  // u_phi is phi_h itself instead of phi_h - phi_o (brdf-tab for anisotropic BRDFs, buildHalfVectorTable);
  // the GLSL part then needs HALF_VECTOR_TABLE_ABSOLUTE_PHI defined.
  bool absolutePhi = false;
};
MerlTableData buildMerlTable(const MerlBrdf& brdf);

// The same tables for any BRDF whose sampling weight w(f(wi, wo)) (e.g. the mean of R, G, B) `weights`
// computes: it receives one batch of grid points per slice (wi above the horizon, and the half vector's
// angles) and fills one weight per point. Negative and non-finite weights count as 0. brdf-tab
// (engine/render/brdf_tabulation.cpp) evaluates them on the GPU with the BRDF's compiled part.
//
// Anisotropic BRDFs (options.absolutePhi): an anisotropic lobe sits at a fixed azimuth of the tangent frame,
// so a table over phi_h - phi_o, built for one view azimuth, puts it in the wrong cells for every other view
// (f cos / pdf reached 150 for Ward 0.05 x 0.3). These tables are over phi_h itself, and each grid point
// takes the largest weight over `viewAzimuths` view azimuths spread over [0, 2 pi) (and both slice edges):
// for microfacet-like BRDFs, whose lobe is fixed in h, the weight varies smoothly with the view's azimuth.
struct HalfVectorTablePoint {
  glm::dvec3 wi, wo;
  double thetaH, sinThetaH, cosThetaH;
  glm::dvec2 phiH;  // (cos, sin) of phi_h
};
using HalfVectorSliceWeights =
    std::function<void(std::span<const HalfVectorTablePoint> points, std::span<double> weights)>;
struct HalfVectorTableOptions {
  bool absolutePhi = false;
  int viewAzimuths = 1;  // with absolutePhi: the view azimuths the envelope is taken over
};
MerlTableData buildHalfVectorTable(const HalfVectorSliceWeights& weights,
                                   const HalfVectorTableOptions& options = {});

// Twin of the GLSL part: slice of wo; row i = largest with marginal[i] <= u.y, column j = largest with
// conditional_i[j] <= u.x (searches in float, zero-width bins never chosen); t offsets as in merl-thetah;
// u_theta = (i + t.y) / ThetaBins; u_phi = (j + t.x) / PhiBins; phi_h = phi_o + 2 pi u_phi with
// phi_o = atan2(wo.y, wo.x) (0 when wo.xy = 0, and always 0 for absolutePhi tables); p(u) = P_row P_col
// ThetaBins PhiBins.
class MerlTableSampler {
 public:
  explicit MerlTableSampler(MerlTableData data);
  BrdfSample sample(glm::dvec2 u, glm::dvec3 wo) const;
  // 0 when wo.z <= 0 or wi = -wo; else the cell of h (see the top) in wo's slice, with
  // u_phi = fract((phi_h - phi_o) / (2 pi)).
  double pdf(glm::dvec3 wi, glm::dvec3 wo) const;
  static int sliceOf(glm::dvec3 wo);
  const MerlTableData& data() const { return data_; }

 private:
  MerlTableData data_;
};

// ---- GPU tables ----
// The MERL BRDF's own table (shaders/brdf/merl.glsl: merlRgb), merl-thetah's CDF
// (shaders/brdf_technique/merl_thetah.glsl: merlThetaHCdf) and the half-vector tables of merl-table and
// brdf-tab (shaders/brdf_technique/half_vector_table.glsl: merlTable, over phi_h itself for absolutePhi
// tables).
TechniqueData merlBrdfTechniqueData(const MerlBrdf& brdf);
TechniqueData merlThetaHTechniqueData(const MerlThetaHData& table);
TechniqueData halfVectorTableTechniqueData(const MerlTableData& table);

}  // namespace iblx
