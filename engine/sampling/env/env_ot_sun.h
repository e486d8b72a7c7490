// Splits an environment's texel weights into a smooth part, which the optimal-transport map carries, and the
// excess of its near-delta texels (suns), which the OT techniques sample directly, texel by texel. A grid of
// bilinear quads cannot follow the map around a sun that holds most of the mass in a few cells: its quads
// twist there and untangling them misplaces up to a third of the mass (docs/ot_solver.md). With the radiance
// capped at a multiple of the median, the rest solves to an injective map. The techniques sample the mixture
//   p(w) = sunShare * pSun(w) + (1 - sunShare) * pOt(w)
// and evaluate both parts' pdfs, so the pdf stays exact.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace iblx {

// Texels brighter than this multiple of the median positive radiance are capped to it. At 100 the OT map of
// the rest has no twisted quad on the default sky (88 % of its mass above the cap) or on sunrise.exr (58 %).
inline constexpr double kOtSunClip = 100.0;
// The split is made only when the capped texels hold at least this share of the weight. Below it the whole
// map untangles with little loss (forest.exr: 13 % above the cap, sampler-map L1 0.058 whole, 0.027 split)
// and the variance per sample was the same with and without the split, while the mixture, which evaluates
// both parts' pdfs, makes each sample cost more (docs/ot_solver.md, "Tried and dropped").
inline constexpr double kOtSunMinShare = 0.25;

struct OtSunSplit {
  int width = 0, height = 0;
  std::vector<double> smoothWeights;  // W*H: min(weight, cap * Omega(y)), what the OT density is built from
  float sunShare = 0.0f;              // the sun part's share of the total weight (0: no texel above the cap)
  std::vector<std::uint32_t> texels;  // the capped texels' indices y*W + x, ascending; at least one entry
  // texels.size() + 1 values: the float CDF over the capped texels' excess weight. A texel's probability is
  // the float difference of its two entries, as the GPU reads it (0 for the placeholder of an empty split).
  std::vector<float> cdf;
  std::vector<std::uint32_t>
      rowFirst;  // H+1: the capped texels of row y are texels[rowFirst[y], rowFirst[y+1])

  // The sun part's probability of texel (x, y) (0 when it is not capped), from the float CDF.
  float texelProbability(int x, int y) const;
};

// weights: W*H texel sampling weights (texelSamplingWeights: radiance times solid angle). clip <= 0 disables
// the split, and so does a sun share below minShare. Throws iblx::Error on mis-sized or negative weights.
OtSunSplit splitOtSun(std::span<const double> weights, int width, int height, double clip = kOtSunClip,
                      double minShare = kOtSunMinShare);

}  // namespace iblx
