// MIT CSAIL anisotropic measured BRDFs in the .dat layout that Disney's BRDF Explorer reads
// (BRDFMeasuredAniso): reading with every check a user needs, writing (for `iblx measured-synth`), and the
// reference lookup in double; the GLSL twin is shaders/brdf/mit.glsl.
//
// The file is a header of 16 little-endian int32 (the bin counts of theta_in, theta_out, phi_diff and phi_in
// at 0-3; the parameterisation at 6, 1 = standard; the binning at 7, 0 = uniform; at 9, 1 when phi_diff
// covers [0, pi] (half data) instead of [0, 2 pi]; the channel count at 10, 3), then channel-planar float32
// with index = iPhiIn + nPhiIn (iPhiDiff + nPhiDiff (iThetaOut + nThetaOut iThetaIn)). "in" is the
// illumination (brdfEval's wi), "out" the view (wo); theta spans [0, pi/2], phi_in [0, 2 pi] from the
// tangent, phi_diff = phi_out - phi_in. The lookup takes the bin floor(angle * n / range), clamped, as BRDF
// Explorer does; with half data phi_diff is folded into [0, pi] by mirror symmetry. Negative entries are
// unmeasured: a bin with one is 0 in all channels, like MERL's invalid bins.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace iblx {

inline constexpr std::size_t kMitHeaderBytes = 64;

struct MitDims {
  int thetaIn = 0, thetaOut = 0, phiDiff = 0, phiIn = 0;
  bool halfData = false;  // phi_diff over [0, pi]
  std::size_t bins() const {
    return std::size_t(thetaIn) * std::size_t(thetaOut) * std::size_t(phiDiff) * std::size_t(phiIn);
  }
  std::size_t index(int iThetaIn, int iThetaOut, int iPhiDiff, int iPhiIn) const {
    return std::size_t(iPhiIn) +
           std::size_t(phiIn) * (std::size_t(iPhiDiff) +
                                 std::size_t(phiDiff) * (std::size_t(iThetaOut) +
                                                         std::size_t(thetaOut) * std::size_t(iThetaIn)));
  }
};

// A loaded material: the stored values as float, planar (rgb[c * bins + index]), unmeasured bins 0.
struct MitBrdf {
  MitDims dims;
  std::vector<float> rgb;
  std::size_t unmeasuredBins = 0;
};

// Whether a file starts like a .dat of this layout: a header with the standard parameterisation, uniform
// binning, 3 channels, positive bin counts, and a size that matches them.
bool looksLikeMitBrdf(const std::filesystem::path& path);

// Reads a .dat file. Throws iblx::Error naming the file on an unreadable file, a header that is not this
// layout (naming the field), bin counts whose table exceeds the memory budget, a size other than the header
// implies (both sizes), or an entry that is not finite or above 1e15. Unmeasured bins become 0, reported in
// one warning with their count.
MitBrdf loadMitBrdf(const std::filesystem::path& path);

// Writes a .dat file: `values` holds 3 * dims.bins() values, planar. Throws iblx::Error when it cannot.
void writeMitBrdf(const std::filesystem::path& path, const MitDims& dims, std::span<const float> values);

// The directions (local frame, normal +z, tangent +x) at the centre of a bin: wi from (theta_in, phi_in), wo
// from (theta_out, phi_in + phi_diff).
struct MitDirectionPair {
  glm::dvec3 wi, wo;
};
MitDirectionPair mitBinCenter(const MitDims& dims, int iThetaIn, int iThetaOut, int iPhiDiff, int iPhiIn);

// f(wi, wo) in 1/sr times `scale`: 0 when either direction is at or below the horizon, else the value of the
// bin of (theta_in, theta_out, phi_diff, phi_in).
glm::dvec3 evalMitBrdf(const MitBrdf& brdf, glm::dvec3 wi, glm::dvec3 wo, double scale = 1.0);

}  // namespace iblx
