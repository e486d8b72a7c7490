// Piecewise-constant CDFs built in double and stored as float, as the GPU techniques read them (env-cdf,
// merl-thetah, merl-table), with the float-exact search and remap their CPU twins share with the GLSL parts.
#pragma once

#include "engine/io/latlong_texel.h"  // kOneMinusEpsilonF

#include <algorithm>
#include <cstdint>
#include <span>

namespace iblx {

// Writes the normalised running sum of `weights` into cdf[0..n] (n = weights.size()): cdf[0] = 0, cdf[n] = 1
// exactly, non-decreasing after rounding to float. All-zero weights become the uniform CDF k/n.
inline void writeFloatCdf(std::span<const double> weights, float* cdf) {
  const std::size_t n = weights.size();
  double total = 0.0;
  for (double w : weights) total += w;
  cdf[0] = 0.0f;
  double running = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    running += weights[k];  // same additions as `total`, so running == total after the last bin
    const double c = total > 0.0 ? running / total : double(k + 1) / double(n);
    cdf[k + 1] = std::max(float(c), cdf[k]);
  }
  cdf[n] = 1.0f;
}

// Bin k in [0, n) with cdf[k] <= u < cdf[k+1]: (first entry among cdf[1..n] greater than u) - 1. Searching
// from entry 1 means a zero-width bin is never returned.
inline int findFloatBin(const float* cdf, int n, float u) {
  const float* first = std::upper_bound(cdf + 1, cdf + n + 1, u);
  return std::clamp(int(first - cdf) - 1, 0, n - 1);
}

// Offset t = (u - lo) / width of u inside its bin, clamped to [0, 1 - 2^-24], in float as on the GPU.
inline float remapInFloatBin(float u, float lo, float width) {
  return width > 0.0f ? std::clamp((u - lo) / width, 0.0f, kOneMinusEpsilonF) : 0.0f;
}

// Guide table (Chen & Asau 1974) of a CDF over n bins with G cells, G a power of two. Cell k: lo = bin of u =
// k/G, hi = bin of the largest float below (k+1)/G. Both bounds are floats exactly (G is a power of two), so
// [lo, hi] holds the bin of every u in the cell.
inline void writeGuide(const float* cdf, int n, int cells, std::uint32_t* guide) {
  for (int k = 0; k < cells; ++k) {
    const float start = float(k) / float(cells), end = float(k + 1) / float(cells);
    const int lo = findFloatBin(cdf, n, start);
    // Largest i with cdf[i] < end: (first entry among cdf[1..n] >= end) - 1.
    const int hi = std::clamp(int(std::lower_bound(cdf + 1, cdf + n + 1, end) - cdf) - 1, lo, n - 1);
    guide[k] = std::uint32_t(lo) | std::uint32_t(hi) << 16;
  }
}

// findFloatBin through guide cell u * G: the same bin, found by a search over [lo, hi] only (as on the GPU).
inline int findBinGuided(const float* cdf, const std::uint32_t* guide, int cells, float u) {
  const std::uint32_t g = guide[std::min(int(u * float(cells)), cells - 1)];
  const int lo = int(g & 0xffffu), hi = int(g >> 16);
  const float* first = std::upper_bound(cdf + lo + 1, cdf + hi + 1, u);
  return int(first - cdf) - 1;
}

}  // namespace iblx
