// Linear-RGB lat-long environment images: loading (.exr, .hdr) with sanitation, and the sampling weight.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <vector>

namespace iblx {

// Row-major, top row (v = 0, theta = 0, +Y) first, 3 floats (R, G, B) per texel, every value finite and >= 0.
struct EnvImage {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;

  std::size_t texelCount() const { return std::size_t(width) * std::size_t(height); }
  std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(width) + std::size_t(x); }
  // Sampling weight of a texel: the mean of R, G and B (docs/DESIGN.md §3).
  double weight(int x, int y) const {
    const float* p = &rgb[3 * index(x, y)];
    return (double(p[0]) + double(p[1]) + double(p[2])) / 3.0;
  }
};

struct SanitizeReport {
  std::size_t nanCount = 0, infCount = 0, negativeCount = 0;
  std::size_t total() const { return nanCount + infCount + negativeCount; }
};

// Replaces NaN and -Inf by 0, +Inf by the largest finite value of the image (0 if none), negatives by 0.
SanitizeReport sanitize(EnvImage& image);

// The largest radiance an environment map may hold. The GPU keeps running means of squared estimates in float
// (docs/DESIGN.md §6): with values up to 1e15, a pass of 4096 squared estimates stays 1e5 below float's 3.4e38 even
// for estimator weights of 100, while real maps, a physically scaled sun included (about 1.6e9 cd/m^2), stay
// far below it.
inline constexpr double kMaxEnvRadiance = 1e15;

// Loads a .exr (OpenEXR; half or float; RGB, RGBA or Y) or .hdr (Radiance RGBE) lat-long map and sanitizes
// it, emitting one warning that counts the fixed texels. A texel above kMaxEnvRadiance is refused (an Error
// naming the file, the texel and the limit), not scaled. Throws iblx::Error naming the file on any failure.
EnvImage loadEnvImage(const std::filesystem::path& path);

// Reads any .exr or .hdr as linear RGB, as it is: no sanitation, no environment-map checks (e.g. a reference
// image written by `iblx reference`). Throws iblx::Error naming the file on any failure.
EnvImage loadRgbImage(const std::filesystem::path& path);
// The same for an OpenEXR file's bytes already in memory (a cache entry whose seal was checked); `name` names
// it in errors.
EnvImage decodeExr(std::span<const unsigned char> bytes, const std::string& name);

}  // namespace iblx
