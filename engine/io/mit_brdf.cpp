// MIT CSAIL anisotropic measured BRDFs: the .dat reader, the writer of `iblx measured-synth`, and the
// reference nearest-bin lookup (mit_brdf.h).
#include "engine/io/mit_brdf.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <numbers>
#include <string>
#include <system_error>

namespace iblx {
namespace {

namespace fs = std::filesystem;

constexpr double kMaxMitValue = 1e15;  // the float headroom of kMaxEnvRadiance (engine/io/env_image.h)
constexpr double kPi = std::numbers::pi;
// Bin counts beyond this are not a measurement but a corrupt header (BRDF Explorer's files use 45 x 45 x 180
// x 90).
constexpr int kMaxMitBinsPerAxis = 4096;

std::int32_t loadLe32(const unsigned char* p) {
  return std::int32_t(std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
                      std::uint32_t(p[3]) << 24);
}

// The header's fields, or the reason it is not this layout (empty when it is).
struct Header {
  MitDims dims;
  std::string problem;
};
Header readHeader(const unsigned char* h) {
  Header header;
  std::int32_t field[16];
  for (int k = 0; k < 16; ++k) field[k] = loadLe32(h + 4 * k);
  const char* names[4] = {"theta_in", "theta_out", "phi_diff", "phi_in"};
  for (int k = 0; k < 4; ++k)
    if (field[k] < 1 || field[k] > kMaxMitBinsPerAxis) {
      header.problem = std::string("header field 0-3 (bin counts): ") + names[k] + " has " +
                       std::to_string(field[k]) + " bins, expected 1 to " +
                       std::to_string(kMaxMitBinsPerAxis);
      return header;
    }
  if (field[6] != 1)
    header.problem =
        "header field 6 (parameterisation) is " + std::to_string(field[6]) + ", expected 1 (standard)";
  else if (field[7] != 0)
    header.problem = "header field 7 (binning) is " + std::to_string(field[7]) + ", expected 0 (uniform)";
  else if (field[9] != 0 && field[9] != 1)
    header.problem = "header field 9 (half data) is " + std::to_string(field[9]) + ", expected 0 or 1";
  else if (field[10] != 3)
    header.problem = "header field 10 (channels) is " + std::to_string(field[10]) + ", expected 3";
  header.dims = {field[0], field[1], field[2], field[3], field[9] == 1};
  return header;
}

std::uint64_t expectedBytes(const MitDims& dims) {
  return kMitHeaderBytes + 3 * 4 * std::uint64_t(dims.bins());
}

int binOf(double angle, double range, int bins) {
  const double x = angle / range * bins;
  if (!(x > 0.0)) return 0;
  return x >= double(bins - 1) ? bins - 1 : int(x);
}

double azimuth(glm::dvec3 w) {
  double phi = std::atan2(w.y, w.x);
  return phi < 0.0 ? phi + 2.0 * kPi : phi;
}

}  // namespace

bool looksLikeMitBrdf(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || size < kMitHeaderBytes) return false;
  std::ifstream in(path, std::ios::binary);
  unsigned char h[kMitHeaderBytes];
  if (!in.read(reinterpret_cast<char*>(h), std::streamsize(kMitHeaderBytes))) return false;
  const Header header = readHeader(h);
  return header.problem.empty() && size == expectedBytes(header.dims);
}

MitBrdf loadMitBrdf(const fs::path& path) {
  const std::string name = path.string();
  const std::uint64_t size = checkInputFile(path);
  if (size < kMitHeaderBytes)
    throw Error(name + ": truncated MIT .dat file: " + std::to_string(size) +
                " bytes, shorter than its 64-byte header");
  std::ifstream in(path, std::ios::binary);
  unsigned char h[kMitHeaderBytes];
  if (!in.read(reinterpret_cast<char*>(h), std::streamsize(kMitHeaderBytes)))
    throw Error(name + ": cannot read the MIT .dat header");
  const Header header = readHeader(h);
  if (!header.problem.empty()) throw Error(name + ": not an MIT .dat BRDF: " + header.problem);
  const MitDims& dims = header.dims;
  checkMemoryBudget(name + ": the " + std::to_string(dims.bins()) + "-bin table",
                    3 * std::uint64_t(dims.bins()) * (sizeof(float) + 4));
  if (size != expectedBytes(dims))
    throw Error(name + ": " + (size < expectedBytes(dims) ? "truncated" : "oversized") +
                " MIT .dat file: " + std::to_string(size) + " bytes, expected " +
                std::to_string(expectedBytes(dims)) + " for its header's " + std::to_string(dims.thetaIn) +
                " x " + std::to_string(dims.thetaOut) + " x " + std::to_string(dims.phiDiff) + " x " +
                std::to_string(dims.phiIn) + " bins x 3 channels");
  checkDeviceTable(name + ": the " + std::to_string(dims.bins()) + "-bin table",
                   3 * std::uint64_t(dims.bins()) * sizeof(float));
  const std::vector<unsigned char> bytes = readInputFile(path, size);
  MitBrdf brdf;
  brdf.dims = dims;
  const std::size_t bins = dims.bins();
  brdf.rgb.resize(3 * bins);
  std::vector<bool> unmeasured(bins, false);
  for (std::size_t k = 0; k < 3 * bins; ++k) {
    const float v = std::bit_cast<float>(std::uint32_t(loadLe32(bytes.data() + kMitHeaderBytes + 4 * k)));
    if (!std::isfinite(v))
      throw Error(name + ": bin " + std::to_string(k % bins) + " of channel " + "RGB"[k / bins] +
                  " is not a finite number");
    if (double(v) > kMaxMitValue)
      throw Error(name + ": bin " + std::to_string(k % bins) + " of channel " + "RGB"[k / bins] + " holds " +
                  std::to_string(v) + ", above the largest BRDF value iblx accepts (1e15)");
    if (v < 0.0f) unmeasured[k % bins] = true;
    brdf.rgb[k] = v;
  }
  for (std::size_t i = 0; i < bins; ++i)
    if (unmeasured[i]) {
      for (int c = 0; c < 3; ++c) brdf.rgb[std::size_t(c) * bins + i] = 0.0f;
      ++brdf.unmeasuredBins;
    }
  if (brdf.unmeasuredBins > 0)
    warn(name + ": " + std::to_string(brdf.unmeasuredBins) + " of " + std::to_string(bins) +
         " bins are unmeasured (negative); they are treated as 0");
  return brdf;
}

void writeMitBrdf(const fs::path& path, const MitDims& dims, std::span<const float> values) {
  const std::string name = path.string();
  if (values.size() != 3 * dims.bins())
    throw Error(name + ": cannot write an MIT .dat file from " + std::to_string(values.size()) +
                " values; its bins need " + std::to_string(3 * dims.bins()));
  std::vector<unsigned char> bytes(expectedBytes(dims), 0);
  const auto put = [&](std::size_t at, std::uint32_t v) {
    for (int b = 0; b < 4; ++b) bytes[at + std::size_t(b)] = static_cast<unsigned char>(v >> (8 * b));
  };
  const int fields[16] = {dims.thetaIn,
                          dims.thetaOut,
                          dims.phiDiff,
                          dims.phiIn,
                          0,
                          0,
                          1,
                          0,
                          0,
                          dims.halfData ? 1 : 0,
                          3,
                          0,
                          0,
                          0,
                          0,
                          0};
  for (int k = 0; k < 16; ++k) put(4 * std::size_t(k), std::uint32_t(fields[k]));
  for (std::size_t k = 0; k < values.size(); ++k)
    put(kMitHeaderBytes + 4 * k, std::bit_cast<std::uint32_t>(values[k]));
  writeFileAtomically(path, bytes);
}

MitDirectionPair mitBinCenter(const MitDims& dims, int iThetaIn, int iThetaOut, int iPhiDiff, int iPhiIn) {
  const double thetaIn = (iThetaIn + 0.5) / dims.thetaIn * 0.5 * kPi;
  const double thetaOut = (iThetaOut + 0.5) / dims.thetaOut * 0.5 * kPi;
  const double phiIn = (iPhiIn + 0.5) / dims.phiIn * 2.0 * kPi;
  const double phiDiff = (iPhiDiff + 0.5) / dims.phiDiff * (dims.halfData ? kPi : 2.0 * kPi);
  const auto dir = [](double theta, double phi) {
    return glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  };
  return {dir(thetaIn, phiIn), dir(thetaOut, phiIn + phiDiff)};
}

glm::dvec3 evalMitBrdf(const MitBrdf& brdf, glm::dvec3 wi, glm::dvec3 wo, double scale) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return glm::dvec3(0.0);
  const MitDims& d = brdf.dims;
  const double phiIn = azimuth(wi);
  double phiDiff = azimuth(wo) - phiIn;
  if (phiDiff < 0.0) phiDiff += 2.0 * kPi;
  if (d.halfData && phiDiff > kPi) phiDiff = 2.0 * kPi - phiDiff;  // mirror symmetry
  const std::size_t index =
      d.index(binOf(std::acos(std::min(wi.z, 1.0)), 0.5 * kPi, d.thetaIn),
              binOf(std::acos(std::min(wo.z, 1.0)), 0.5 * kPi, d.thetaOut),
              binOf(phiDiff, d.halfData ? kPi : 2.0 * kPi, d.phiDiff), binOf(phiIn, 2.0 * kPi, d.phiIn));
  const std::size_t bins = d.bins();
  return scale * glm::dvec3(brdf.rgb[index], brdf.rgb[bins + index], brdf.rgb[2 * bins + index]);
}

}  // namespace iblx
