// MERL isotropic measured BRDFs: the .binary reader (size, header and value checks, invalid bins zeroed with
// one counting warning), the writer used by `iblx merl-synth`, and the reference half/difference-angle
// lookup.
#include "engine/io/merl.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <system_error>

namespace iblx {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = std::numbers::pi;
constexpr double kHalfPi = 0.5 * std::numbers::pi;
constexpr int kHeaderDims[3] = {kMerlThetaHBins, kMerlThetaDBins, kMerlPhiDBins};
constexpr std::size_t kHeaderBytes = 12;
// Doubles per read or write: 512 KiB of bytes, so the 35 MB body is never held twice.
constexpr std::size_t kChunkDoubles = std::size_t(1) << 16;
// The largest reflectance a bin may hold, for the same float headroom as kMaxEnvRadiance
// (engine/io/env_image.h): measured materials stay below about 1e4 1/sr.
constexpr double kMaxMerlValue = 1e15;

std::string formatValue(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// The file's byte order is little-endian whatever the host's; these compile to plain loads and stores on
// little-endian machines.
std::uint32_t loadLe32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}
std::uint64_t loadLe64(const unsigned char* p) {
  return std::uint64_t(loadLe32(p)) | std::uint64_t(loadLe32(p + 4)) << 32;
}
void storeLe32(std::uint32_t v, unsigned char* p) {
  for (int b = 0; b < 4; ++b) p[b] = static_cast<unsigned char>(v >> (8 * b));
}
void storeLe64(std::uint64_t v, unsigned char* p) {
  for (int b = 0; b < 8; ++b) p[b] = static_cast<unsigned char>(v >> (8 * b));
}

std::string systemReason() {
  return errno != 0 ? std::string(std::strerror(errno)) : std::string("unknown error");
}

// Rotation about z by angle a: (x cos a - y sin a, x sin a + y cos a, z).
glm::dvec3 rotateZ(glm::dvec3 v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {v.x * c - v.y * s, v.x * s + v.y * c, v.z};
}

// Rotation about y by angle a: (x cos a + z sin a, y, -x sin a + z cos a).
glm::dvec3 rotateY(glm::dvec3 v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {v.x * c + v.z * s, v.y, -v.x * s + v.z * c};
}

}  // namespace

MerlBrdf loadMerl(const fs::path& path) {
  const std::string name = path.string();
  // Size first: it tells truncated and oversized files apart before any value is read (and a FIFO or device
  // is refused before it is opened).
  const std::uint64_t size = checkInputFile(path);
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(name + ": cannot open: " + systemReason());
  if (size != kMerlFileBytes)
    throw Error(name + ": " + (size < kMerlFileBytes ? "truncated" : "oversized") + " MERL file: " +
                std::to_string(size) + " bytes, expected exactly " + std::to_string(kMerlFileBytes) +
                " (a 12-byte header and 3 x " + std::to_string(kMerlBins) + " doubles)");

  unsigned char header[kHeaderBytes];
  if (!in.read(reinterpret_cast<char*>(header), std::streamsize(kHeaderBytes)))
    throw Error(name + ": read error in the MERL header (the file may have changed while reading)");
  const std::int32_t dims[3] = {std::int32_t(loadLe32(header)), std::int32_t(loadLe32(header + 4)),
                                std::int32_t(loadLe32(header + 8))};
  if (dims[0] != kHeaderDims[0] || dims[1] != kHeaderDims[1] || dims[2] != kHeaderDims[2])
    throw Error(name + ": MERL header has dimensions (" + std::to_string(dims[0]) + ", " +
                std::to_string(dims[1]) + ", " + std::to_string(dims[2]) + "), expected (90, 90, 180) " +
                "(theta_h, theta_d, phi_d bins); this is not an isotropic MERL .binary file");

  // Body: planar doubles, scaled per channel and stored as float. A channel value that is negative or not
  // finite, or beyond float range once scaled, is marked NaN here; the bin is zeroed in the pass below.
  MerlBrdf brdf;
  brdf.rgb.resize(3 * kMerlBins);
  constexpr float kInvalid = std::numeric_limits<float>::quiet_NaN();
  std::vector<unsigned char> chunk(kChunkDoubles * 8);
  for (int c = 0; c < 3; ++c) {
    const double scale = kMerlChannelScale[std::size_t(c)];
    float* out = brdf.rgb.data() + std::size_t(c) * kMerlBins;
    for (std::size_t first = 0; first < kMerlBins; first += kChunkDoubles) {
      const std::size_t count = std::min(kChunkDoubles, kMerlBins - first);
      if (!in.read(reinterpret_cast<char*>(chunk.data()), std::streamsize(count * 8)))
        throw Error(name + ": read error after " +
                    std::to_string(kHeaderBytes + (c * kMerlBins + first) * 8) +
                    " bytes (the file may have been truncated while reading)");
      for (std::size_t k = 0; k < count; ++k) {
        // The range check comes first: converting a double beyond FLT_MAX to float is undefined.
        const double v = std::bit_cast<double>(loadLe64(chunk.data() + 8 * k)) * scale;
        if (std::isfinite(v) && v > kMaxMerlValue)
          throw Error(name + ": bin " + std::to_string(first + k) + " of channel " + "RGB"[c] + " holds " +
                      formatValue(v) + ", above the largest BRDF value iblx accepts (1e15)");
        out[first + k] = v >= 0.0 && v <= kMaxMerlValue ? float(v) : kInvalid;
      }
    }
  }

  // A bin with any invalid channel is 0 in all three ("below horizon" in MERL's reference code), so that
  // evaluation, the sampling tables and the ground truth all see the same material.
  float* r = brdf.rgb.data();
  float* g = r + kMerlBins;
  float* b = g + kMerlBins;
  for (std::size_t i = 0; i < kMerlBins; ++i) {
    if (std::isnan(r[i]) || std::isnan(g[i]) || std::isnan(b[i])) {
      r[i] = g[i] = b[i] = 0.0f;
      ++brdf.invalidBins;
    }
  }
  if (brdf.invalidBins > 0)
    warn(name + ": " + std::to_string(brdf.invalidBins) + " of " + std::to_string(kMerlBins) +
         " MERL bins are invalid (negative or non-finite); they are treated as 0 in evaluation, sampling and "
         "the reference");
  return brdf;
}

void writeMerl(const fs::path& path, std::span<const double> values) {
  const std::string name = path.string();
  if (values.size() != 3 * kMerlBins)
    throw Error(name + ": cannot write a MERL file from " + std::to_string(values.size()) +
                " values; it needs 3 x " + std::to_string(kMerlBins) + " = " + std::to_string(3 * kMerlBins));
  AtomicOutput output(path);
  std::ofstream& out = output.stream();

  unsigned char header[kHeaderBytes];
  for (int d = 0; d < 3; ++d) storeLe32(std::uint32_t(kHeaderDims[d]), header + 4 * d);
  out.write(reinterpret_cast<const char*>(header), std::streamsize(kHeaderBytes));

  std::vector<unsigned char> chunk(kChunkDoubles * 8);
  for (int c = 0; c < 3 && out; ++c) {
    const double scale = kMerlChannelScale[std::size_t(c)];
    const double* in = values.data() + std::size_t(c) * kMerlBins;
    for (std::size_t first = 0; first < kMerlBins && out; first += kChunkDoubles) {
      const std::size_t count = std::min(kChunkDoubles, kMerlBins - first);
      for (std::size_t k = 0; k < count; ++k)
        storeLe64(std::bit_cast<std::uint64_t>(in[first + k] / scale), chunk.data() + 8 * k);
      out.write(reinterpret_cast<const char*>(chunk.data()), std::streamsize(count * 8));
    }
  }
  output.commit();
}

MerlAngles merlAngles(glm::dvec3 wi, glm::dvec3 wo) {
  // Half vector; wi = -wo has none, and the normal stands in for it.
  glm::dvec3 h = wi + wo;
  const double length = glm::length(h);
  h = length > 0.0 ? h / length : glm::dvec3(0.0, 0.0, 1.0);
  MerlAngles a;
  a.thetaH = std::acos(std::clamp(h.z, -1.0, 1.0));
  const double phiH = std::atan2(h.y, h.x);
  // wi in the half-vector frame: rotate by -phi_h about the normal, then by -theta_h about the bitangent.
  const glm::dvec3 diff = rotateY(rotateZ(wi, -phiH), -a.thetaH);
  a.thetaD = std::acos(std::clamp(diff.z, -1.0, 1.0));
  // phi_d and phi_d + pi are the same bin (reciprocity): fold to [0, pi). atan2 may return exactly pi, and
  // -tiny + pi rounds to pi; both are the fold's seam, which maps to 0.
  a.phiD = std::atan2(diff.y, diff.x);
  if (a.phiD < 0.0) a.phiD += kPi;
  if (a.phiD >= kPi) a.phiD = 0.0;
  return a;
}

glm::ivec3 merlBin(const MerlAngles& angles) {
  // theta_h: square-root warp, 0 for theta_h <= 0; theta_d and phi_d: linear.
  const int thetaH = angles.thetaH > 0.0 ? merlCellIndex(std::sqrt(angles.thetaH / kHalfPi) * kMerlThetaHBins,
                                                         kMerlThetaHBins)
                                         : 0;
  const int thetaD = merlCellIndex(angles.thetaD / kHalfPi * kMerlThetaDBins, kMerlThetaDBins);
  const int phiD = merlCellIndex(angles.phiD / kPi * kMerlPhiDBins, kMerlPhiDBins);
  return {thetaH, thetaD, phiD};
}

DirectionPair merlBinCenter(int thetaH, int thetaD, int phiD) {
  const double u = (thetaH + 0.5) / kMerlThetaHBins;
  const double th = u * u * kHalfPi;
  const double td = (thetaD + 0.5) / kMerlThetaDBins * kHalfPi;
  const double pd = (phiD + 0.5) / kMerlPhiDBins * kPi;
  // wi in the half-vector frame, rotated back by +theta_h about y (phi_h = 0); wo is its mirror about h.
  const glm::dvec3 d(std::sin(td) * std::cos(pd), std::sin(td) * std::sin(pd), std::cos(td));
  DirectionPair pair;
  pair.wi = rotateY(d, th);
  const glm::dvec3 h(std::sin(th), 0.0, std::cos(th));
  pair.wo = 2.0 * glm::dot(h, pair.wi) * h - pair.wi;
  return pair;
}

glm::dvec3 evalMerl(const MerlBrdf& brdf, glm::dvec3 wi, glm::dvec3 wo) {
  IBLX_ASSERT(brdf.rgb.size() == 3 * kMerlBins);
  if (!(wi.z > 0.0) || !(wo.z > 0.0)) return glm::dvec3(0.0);
  const glm::ivec3 bin = merlBin(merlAngles(wi, wo));
  const std::size_t i = merlBinIndex(bin.x, bin.y, bin.z);
  return {brdf.rgb[i], brdf.rgb[kMerlBins + i], brdf.rgb[2 * kMerlBins + i]};
}

}  // namespace iblx
