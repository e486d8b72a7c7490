// The OT solver's density (density.h): texel weights integrated over the grid's cells, along u by length
// and along v by solid angle.
#include "engine/ot/density.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"
#include "engine/io/latlong_texel.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace iblx {

std::vector<double> otDensityFromEnv(const EnvImage& env, int n) {
  // Texel masses w = L * Omega(y) (solid angle included); texelSamplingWeights validates the image and maps
  // an all-black image to the uniform sphere.
  return otDensityFromWeights(texelSamplingWeights(env, "OT density"), env.width, env.height, n);
}

std::vector<double> otDensityFromWeights(std::span<const double> weights, int width, int height, int n) {
  if (n < 1) throw Error("OT density: the grid size must be at least 1, got " + std::to_string(n));
  if (width < 1 || height < 1 || weights.size() != std::size_t(width) * height)
    throw Error("OT density: expected " + std::to_string(width) + " x " + std::to_string(height) +
                " weights");
  const auto index = [width](int x, int y) { return std::size_t(y) * width + x; };
  // Pass 1, along u: per texel row y, the texel mass falling in each grid column (exact length overlap).
  std::vector<double> rows(std::size_t(height) * n, 0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double w = weights[index(x, y)];
      if (w == 0.0) continue;
      const double u0 = double(x) / width, u1 = double(x + 1) / width;
      for (int c = std::max(0, int(std::floor(u0 * n))); c < std::min(n, int(std::ceil(u1 * n))); ++c) {
        const double overlap = std::min(u1, double(c + 1) / n) - std::max(u0, double(c) / n);
        if (overlap > 0.0) rows[std::size_t(y) * n + c] += w * overlap * width;
      }
    }
  // Pass 2, along v: the share of texel row y's solid angle inside grid row r is (cos ta - cos tb) / (cos t0
  // - cos t1) over the overlap [ta, tb], exact for the nearest-texel radiance (dOmega = dphi dcos(theta)).
  std::vector<double> density(std::size_t(n) * n, 0.0);
  for (int y = 0; y < height; ++y) {
    const double v0 = double(y) / height, v1 = double(y + 1) / height, full = cosDifferenceOfV(v0, v1);
    for (int r = std::max(0, int(std::floor(v0 * n))); r < std::min(n, int(std::ceil(v1 * n))); ++r) {
      const double a = std::max(v0, double(r) / n), b = std::min(v1, double(r + 1) / n);
      if (b <= a) continue;
      const double share = cosDifferenceOfV(a, b) / full;
      for (int c = 0; c < n; ++c) density[std::size_t(r) * n + c] += share * rows[std::size_t(y) * n + c];
    }
  }
  double total = 0.0;
  for (double v : density) total += v;
  if (!(total > 0.0)) throw Error("OT density: the weights are zero everywhere");
  const double scale = double(n) * n / total;  // cells have equal parameter area: mass -> mean-1 density
  for (double& v : density) v *= scale;
  return density;
}

}  // namespace iblx
