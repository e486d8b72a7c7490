// UTIA anisotropic measured BRDFs: the .bin reader, the writer of `iblx measured-synth`, and the reference
// quadrilinear lookup (utia.h).
#include "engine/io/utia.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"
#include "engine/io/image_write.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <system_error>

namespace iblx {
namespace {

namespace fs = std::filesystem;

// The largest value an entry may hold, for the same float headroom as kMaxEnvRadiance
// (engine/io/env_image.h).
constexpr double kMaxUtiaValue = 1e15;
constexpr double kDegree = std::numbers::pi / 180.0;

std::uint64_t loadLe64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int b = 7; b >= 0; --b) v = v << 8 | p[b];
  return v;
}

// "channel G at theta_i 30, phi_i 7.5, theta_v 15, phi_v 0 deg" for entry `index` of channel c.
std::string describeEntry(int c, std::size_t index) {
  const int phiV = int(index % kUtiaPhiSteps), thetaV = int(index / kUtiaPhiSteps % kUtiaThetaSteps);
  const int phiI = int(index / (std::size_t(kUtiaPhiSteps) * kUtiaThetaSteps) % kUtiaPhiSteps);
  const int thetaI = int(index / (std::size_t(kUtiaPhiSteps) * kUtiaThetaSteps * kUtiaPhiSteps));
  char text[128];
  std::snprintf(text, sizeof text, "channel %c at theta_i %g, phi_i %g, theta_v %g, phi_v %g deg", "RGB"[c],
                thetaI * kUtiaThetaStepDeg, phiI * kUtiaPhiStepDeg, thetaV * kUtiaThetaStepDeg,
                phiV * kUtiaPhiStepDeg);
  return text;
}

// The lower grid index and the weight of the upper one of a direction's theta (clamped to the last sample)
// and phi (wrapping).
struct GridCoordinate {
  int theta0 = 0, phi0 = 0, phi1 = 0;
  double thetaWeight = 0.0, phiWeight = 0.0;
};
GridCoordinate gridCoordinate(glm::dvec3 w) {
  GridCoordinate g;
  const double theta = std::acos(std::clamp(w.z, -1.0, 1.0)) / (kUtiaThetaStepDeg * kDegree);
  const double t = std::clamp(theta, 0.0, double(kUtiaThetaSteps - 1));
  g.theta0 = std::min(int(t), kUtiaThetaSteps - 2);
  g.thetaWeight = t - g.theta0;
  double phi = std::atan2(w.y, w.x);
  if (phi < 0.0) phi += 2.0 * std::numbers::pi;
  const double p = phi / (kUtiaPhiStepDeg * kDegree);
  const double floorP = std::floor(p);
  g.phi0 = int(floorP) % kUtiaPhiSteps;
  g.phi1 = (g.phi0 + 1) % kUtiaPhiSteps;
  g.phiWeight = p - floorP;
  return g;
}

}  // namespace

bool looksLikeUtia(const fs::path& path) {
  std::error_code ec;
  return fs::is_regular_file(path, ec) && fs::file_size(path, ec) == kUtiaFileBytes && !ec;
}

UtiaBrdf loadUtia(const fs::path& path) {
  const std::string name = path.string();
  const std::uint64_t size = checkInputFile(path);
  if (size != kUtiaFileBytes)
    throw Error(name + ": " + (size < kUtiaFileBytes ? "truncated" : "oversized") +
                " UTIA file: " + std::to_string(size) + " bytes, expected exactly " +
                std::to_string(kUtiaFileBytes) + " (3 x " + std::to_string(kUtiaEntries) +
                " doubles: 6 theta_i x 48 phi_i x 6 theta_v x 48 phi_v)");
  const std::vector<unsigned char> bytes = readInputFile(path, kUtiaFileBytes);
  UtiaBrdf brdf;
  brdf.rgb.resize(3 * kUtiaEntries);
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < kUtiaEntries; ++i) {
      const std::size_t k = std::size_t(c) * kUtiaEntries + i;
      const double v = std::bit_cast<double>(loadLe64(bytes.data() + 8 * k));
      if (!std::isfinite(v)) throw Error(name + ": " + describeEntry(c, i) + " is not a finite number");
      if (v > kMaxUtiaValue)
        throw Error(name + ": " + describeEntry(c, i) + " holds " + std::to_string(v) +
                    ", above the largest BRDF value iblx accepts (1e15)");
      if (v < 0.0) ++brdf.negativeEntries;
      brdf.rgb[k] = v > 0.0 ? float(v) : 0.0f;
    }
  if (brdf.negativeEntries > 0)
    warn(name + ": " + std::to_string(brdf.negativeEntries) + " of " + std::to_string(3 * kUtiaEntries) +
         " UTIA entries are negative; they are treated as 0");
  return brdf;
}

void writeUtia(const fs::path& path, std::span<const double> values) {
  const std::string name = path.string();
  if (values.size() != 3 * kUtiaEntries)
    throw Error(name + ": cannot write a UTIA file from " + std::to_string(values.size()) +
                " values; it needs 3 x " + std::to_string(kUtiaEntries));
  std::vector<unsigned char> bytes(kUtiaFileBytes);
  for (std::size_t k = 0; k < values.size(); ++k) {
    const std::uint64_t v = std::bit_cast<std::uint64_t>(values[k]);
    for (int b = 0; b < 8; ++b) bytes[8 * k + std::size_t(b)] = static_cast<unsigned char>(v >> (8 * b));
  }
  writeFileAtomically(path, bytes);
}

glm::dvec3 utiaDirection(int thetaIndex, int phiIndex) {
  const double theta = thetaIndex * kUtiaThetaStepDeg * kDegree, phi = phiIndex * kUtiaPhiStepDeg * kDegree;
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

glm::dvec3 evalUtia(const UtiaBrdf& brdf, glm::dvec3 wi, glm::dvec3 wo, const UtiaConvention& convention) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return glm::dvec3(0.0);
  const GridCoordinate gi = gridCoordinate(wi), gv = gridCoordinate(wo);
  glm::dvec3 f(0.0);
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c)
        for (int d = 0; d < 2; ++d) {
          const double weight =
              (a ? gi.thetaWeight : 1.0 - gi.thetaWeight) * (b ? gi.phiWeight : 1.0 - gi.phiWeight) *
              (c ? gv.thetaWeight : 1.0 - gv.thetaWeight) * (d ? gv.phiWeight : 1.0 - gv.phiWeight);
          const std::size_t index =
              utiaIndex(gi.theta0 + a, b ? gi.phi1 : gi.phi0, gv.theta0 + c, d ? gv.phi1 : gv.phi0);
          for (int ch = 0; ch < 3; ++ch)
            f[ch] += weight * double(brdf.rgb[std::size_t(ch) * kUtiaEntries + index]);
        }
  for (int ch = 0; ch < 3; ++ch) {
    const double v = std::max(f[ch], 0.0) * convention.prescale;
    f[ch] = convention.scale * (convention.srgb ? srgbToLinear(v) : v);
  }
  return f;
}

}  // namespace iblx
