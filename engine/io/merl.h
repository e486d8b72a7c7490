// MERL isotropic measured BRDFs (Matusik et al. 2003) in their .binary layout: reading with every check a
// user needs, writing (for `iblx merl-synth`), and the reference lookup in double. The layout, scales and
// index mapping are those of the MERL database's reference reader (BRDFRead.cpp, distributed with the data)
// and of BRDF Explorer's BRDFMeasuredMERL (github.com/wdas/brdf); the GLSL twin is shaders/brdf/merl.glsl.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace iblx {

// Table dimensions: theta_h (square-root warped), theta_d (linear), phi_d over [0, pi) (linear).
inline constexpr int kMerlThetaHBins = 90, kMerlThetaDBins = 90, kMerlPhiDBins = 180;
inline constexpr std::size_t kMerlBins =
    std::size_t(kMerlThetaHBins) * kMerlThetaDBins * kMerlPhiDBins;  // 1,458,000
// Per-channel factors applied to the stored doubles (MERL reference code).
inline constexpr std::array<double, 3> kMerlChannelScale{1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};
// Header (3 x int32) + 3 x kMerlBins float64.
inline constexpr std::uintmax_t kMerlFileBytes = 12 + 3 * kMerlBins * 8;

// A loaded material: reflectance in 1/sr, scales applied, as float (what the GPU reads), planar like the
// file: rgb[c * kMerlBins + bin]. Invalid bins (any channel negative or non-finite; MERL's "below horizon"
// -1) are stored as 0 in all three channels, so evaluation, sampling tables and the ground truth agree.
struct MerlBrdf {
  std::vector<float> rgb;       // 3 * kMerlBins
  std::size_t invalidBins = 0;  // bins replaced by 0
};

// Flat bin index of (theta_h, theta_d, phi_d) bin indices: phiD + 180 * (thetaD + 90 * thetaH).
inline std::size_t merlBinIndex(int thetaH, int thetaD, int phiD) {
  return std::size_t(phiD) + std::size_t(kMerlPhiDBins) *
                                 (std::size_t(thetaD) + std::size_t(kMerlThetaDBins) * std::size_t(thetaH));
}

// int(x) clamped to [0, n - 1]; 0 for x <= 0 and NaN (int() of either would be wrong or undefined). The bin
// or cell of a coordinate x = u * n, for the lookup and the sampling tables alike.
inline int merlCellIndex(double x, int n) {
  if (!(x > 0.0)) return 0;
  return x >= double(n - 1) ? n - 1 : int(x);
}

// Sampling weight of a bin: the mean of its R, G and B (the project's weight, as for environment texels).
inline double merlSamplingWeight(const MerlBrdf& brdf, std::size_t bin) {
  return (double(brdf.rgb[bin]) + double(brdf.rgb[kMerlBins + bin]) + double(brdf.rgb[2 * kMerlBins + bin])) /
         3.0;
}

// Reads a .binary file. Throws iblx::Error naming the file on: unreadable file, size other than
// kMerlFileBytes (truncated or oversized, with both sizes in the message), header other than (90, 90, 180).
// Invalid bins are zeroed and reported in one warning (engine/core/log.h) with their count.
MerlBrdf loadMerl(const std::filesystem::path& path);

// Writes `values` (3 * kMerlBins reflectances in 1/sr, planar, scales NOT applied) as a .binary file: the
// stored doubles are value / kMerlChannelScale[c]. Negative values are written as they are (to make files
// with invalid entries). Throws iblx::Error when the file cannot be written.
void writeMerl(const std::filesystem::path& path, std::span<const double> values);

// Half/difference angles of a direction pair (Rusinkiewicz 1998), as MERL's reference code computes them:
// h = normalize(wi + wo), theta_h = acos(h.z), theta_d = acos(h . wi), phi_d = azimuth of wi after rotating
// by -phi_h about z and -theta_h about y, folded to [0, pi) by adding pi when negative
// (reciprocity/isotropy).
struct MerlAngles {
  double thetaH = 0.0, thetaD = 0.0, phiD = 0.0;
};
MerlAngles merlAngles(glm::dvec3 wi, glm::dvec3 wo);

// Nearest-lower bin of each angle, as the reference lookup: thetaH index clamp(int(sqrt(thetaH / (pi/2)) *
// 90), 0, 89) (0 for thetaH <= 0), thetaD index clamp(int(thetaD / (pi/2) * 90), 0, 89), phiD index
// clamp(int(phiD / pi * 180), 0, 179).
glm::ivec3 merlBin(const MerlAngles& angles);

// Directions in the local frame (normal +z) whose angles are the centre of bin (thetaH, thetaD, phiD) with
// phi_h = 0: theta_h = ((i + 0.5) / 90)^2 pi/2, theta_d = (j + 0.5) / 90 * pi/2, phi_d = (k + 0.5) / 180 *
// pi. One of them may lie below the horizon for large theta_h + theta_d.
struct DirectionPair {
  glm::dvec3 wi, wo;
};
DirectionPair merlBinCenter(int thetaH, int thetaD, int phiD);

// f(wi, wo) in 1/sr for local-frame unit vectors: 0 when either is at or below the horizon (z <= 0),
// otherwise the value of the bin merlBin(merlAngles(wi, wo)).
glm::dvec3 evalMerl(const MerlBrdf& brdf, glm::dvec3 wi, glm::dvec3 wo);

}  // namespace iblx
