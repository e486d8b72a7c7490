// The sun / smooth split of an environment for the OT techniques (env_ot_sun.h).
#include "engine/sampling/env/env_ot_sun.h"

#include "engine/core/error.h"
#include "engine/io/latlong_texel.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace iblx {

float OtSunSplit::texelProbability(int x, int y) const {
  const std::uint32_t index = std::uint32_t(y) * std::uint32_t(width) + std::uint32_t(x);
  const auto first = texels.begin() + rowFirst[std::size_t(y)], last = texels.begin() + rowFirst[y + 1];
  const auto it = std::lower_bound(first, last, index);
  if (it == last || *it != index) return 0.0f;
  const std::size_t k = std::size_t(it - texels.begin());
  return cdf[k + 1] - cdf[k];
}

OtSunSplit splitOtSun(std::span<const double> weights, int width, int height, double clip, double minShare) {
  if (width < 1 || height < 1 || weights.size() != std::size_t(width) * height)
    throw Error("OT sun split: expected " + std::to_string(width) + " x " + std::to_string(height) +
                " weights");
  OtSunSplit split;
  split.width = width;
  split.height = height;
  split.smoothWeights.assign(weights.begin(), weights.end());
  split.rowFirst.assign(std::size_t(height) + 1, 0);
  std::vector<double> omega(static_cast<std::size_t>(height)), radiance;
  for (int y = 0; y < height; ++y) omega[std::size_t(y)] = latLongTexelSolidAngle(y, width, height);
  double total = 0.0;
  for (std::size_t t = 0; t < weights.size(); ++t) {
    if (!(weights[t] >= 0.0) || !std::isfinite(weights[t]))
      throw Error("OT sun split: texel weights must be finite and non-negative");
    total += weights[t];
    if (weights[t] > 0.0) radiance.push_back(weights[t] / omega[t / std::size_t(width)]);
  }
  std::vector<double> excess;
  if (clip > 0.0 && !radiance.empty()) {
    // The median of the positive texels, so that large black regions do not pull the cap to 0.
    const auto middle = radiance.begin() + std::ptrdiff_t(radiance.size() / 2);
    std::nth_element(radiance.begin(), middle, radiance.end());
    const double cap = clip * *middle;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const std::size_t t = std::size_t(y) * width + x;
        const double limit = cap * omega[std::size_t(y)];
        if (!(weights[t] > limit)) continue;
        split.texels.push_back(std::uint32_t(t));
        excess.push_back(weights[t] - limit);
        split.smoothWeights[t] = limit;
      }
      split.rowFirst[std::size_t(y) + 1] = std::uint32_t(split.texels.size());
    }
  }
  double sunWeight = 0.0;
  for (const double e : excess) sunWeight += e;
  if (split.texels.empty() || !(sunWeight >= minShare * total)) {
    // Nothing to split: the whole weight goes to the map, and a zero-probability placeholder keeps the
    // buffers non-empty.
    split.smoothWeights.assign(weights.begin(), weights.end());
    split.texels.assign(1, 0);
    split.cdf = {0.0f, 0.0f};
    std::fill(split.rowFirst.begin(), split.rowFirst.end(), 0u);
    return split;
  }
  split.sunShare = float(sunWeight / total);
  split.cdf.assign(split.texels.size() + 1, 0.0f);
  double running = 0.0;
  for (std::size_t k = 0; k < excess.size(); ++k) {
    running += excess[k];
    split.cdf[k + 1] = float(running / sunWeight);
  }
  split.cdf.back() = 1.0f;
  return split;
}

}  // namespace iblx
