// UTIA anisotropic measured BRDFs (Filip & Vávra 2014, "Template-based sampling of anisotropic BRDFs", the
// UTIA BRDF database) in their .bin layout: reading with every check a user needs, writing (for `iblx
// measured-synth`), and the reference lookup in double; the GLSL twin is shaders/brdf/utia.glsl.
//
// The file has no header: little-endian float64, channel-planar, [3 channels][6 theta_i][48 phi_i][6 theta_v]
// [48 phi_v], theta = 15 deg * k (0 to 75 deg), phi = 7.5 deg * k, both azimuths absolute in the tangent
// frame (phi = atan2(y, x), x the tangent). i is the illumination (brdfEval's wi), v the view (wo).
//
// The lookup is quadrilinear, wrapping in phi. Above 75 deg, where the data has no samples, theta is clamped
// to 75 deg (public readers extrapolate the last interval linearly, which can turn negative). The stored
// values' colour and scale are not absolute 1/sr and readers disagree on them, so iblx applies a documented
// convention with parameters (UtiaConvention): by default the values are linear RGB in 1/sr as stored.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace iblx {

inline constexpr int kUtiaThetaSteps = 6, kUtiaPhiSteps = 48;
inline constexpr double kUtiaThetaStepDeg = 15.0, kUtiaPhiStepDeg = 7.5;
inline constexpr std::size_t kUtiaEntries =
    std::size_t(kUtiaThetaSteps) * kUtiaPhiSteps * kUtiaThetaSteps * kUtiaPhiSteps;  // 82,944 per channel
inline constexpr std::uintmax_t kUtiaFileBytes = 3 * kUtiaEntries * 8;               // 1,990,656

// The flat index of an entry within one channel: ((iThetaI * 48 + iPhiI) * 6 + iThetaV) * 48 + iPhiV.
inline std::size_t utiaIndex(int thetaI, int phiI, int thetaV, int phiV) {
  return ((std::size_t(thetaI) * kUtiaPhiSteps + std::size_t(phiI)) * kUtiaThetaSteps + std::size_t(thetaV)) *
             kUtiaPhiSteps +
         std::size_t(phiV);
}

// A loaded material: the stored values as float, planar like the file (rgb[c * kUtiaEntries + index]),
// negative entries replaced by 0.
struct UtiaBrdf {
  std::vector<float> rgb;           // 3 * kUtiaEntries
  std::size_t negativeEntries = 0;  // entries replaced by 0
};

// What a stored value v means: f = scale * decode(prescale * v), decode the sRGB EOTF when srgb, else the
// identity. Default: linear 1/sr as stored. One public reader's reading of the database is prescale 1/140,
// srgb, scale 100.
struct UtiaConvention {
  double prescale = 1.0;
  bool srgb = false;
  double scale = 1.0;
};

// Whether a file has the .bin layout: a regular file of exactly kUtiaFileBytes (it has no header to check).
bool looksLikeUtia(const std::filesystem::path& path);

// Reads a .bin file. Throws iblx::Error naming the file on an unreadable file, a size other than
// kUtiaFileBytes (both sizes in the message), or an entry that is not finite or above 1e15 (named by its
// channel and angles). Negative entries become 0, reported in one warning with their count.
UtiaBrdf loadUtia(const std::filesystem::path& path);

// Writes 3 * kUtiaEntries values (planar, as stored) as a .bin file. Throws iblx::Error when it cannot.
void writeUtia(const std::filesystem::path& path, std::span<const double> values);

// The local-frame direction (normal +z, tangent +x) of theta index i and phi index j.
glm::dvec3 utiaDirection(int thetaIndex, int phiIndex);

// f(wi, wo) in 1/sr under `convention`: 0 when either direction is at or below the horizon, else the
// quadrilinear lookup described above, negative results clamped to 0.
glm::dvec3 evalUtia(const UtiaBrdf& brdf, glm::dvec3 wi, glm::dvec3 wo,
                    const UtiaConvention& convention = {});

}  // namespace iblx
