// env-cdf: marginal/conditional piecewise-constant CDFs over the texels of a lat-long map (builder + CPU twin
// of shaders/env_technique/env_cdf.glsl).
#pragma once

#include "engine/io/env_image.h"
#include "engine/io/latlong_texel.h"
#include "engine/sampling/technique_data.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace iblx {

// GPU data of env-cdf (two std430 float arrays, plus rowSolidAngles(width, height) as a third).
// Texel weight w(x, y) = image.weight(x, y) * Omega(y); row weight = sum over x; all sums in double,
// normalised in double, stored as float with the last entry of every CDF forced to exactly 1.0f. Every CDF is
// non-decreasing after rounding. An all-zero row has the uniform conditional x/W; an all-zero image has the
// marginal proportional to Omega(y) (uniform sphere).
struct EnvCdfData {
  int width = 0, height = 0;
  std::vector<float> marginalCdf;     // H+1 entries, [0] = 0, [H] = 1 exactly, non-decreasing
  std::vector<float> conditionalCdf;  // H*(W+1) entries, row y at y*(W+1), each row [0] = 0, [W] = 1 exactly
  // Guide tables (Chen & Asau's "index table", 1974) that shorten the searches: a CDF over n bins gets
  // G cells, a power of two so that u * G and k / G are exact in float. Cell k packs
  // lo | hi << 16, the bins of u = k/G and of the largest float below (k+1)/G, so the bin of any u in the
  // cell lies in [lo, hi] and a search of ceil(log2(hi - lo + 1)) steps finds it (usually 0 or 1).
  int rowGuideCells = 0;                        // envCdfGuideCells(H, kEnvCdfRowCellsPerBin)
  int columnGuideCells = 0;                     // envCdfGuideCells(W, kEnvCdfColumnCellsPerBin)
  std::vector<std::uint32_t> marginalGuide;     // rowGuideCells cells
  std::vector<std::uint32_t> conditionalGuide;  // H * columnGuideCells cells, row y at y * columnGuideCells
};

// Cells of the guide table of a CDF over n bins: the largest power of two <= n * cellsPerBin, so between
// cellsPerBin / 2 and cellsPerBin cells per bin (the conditionals' guides take at most 8 bytes per texel,
// less than the map itself). More cells mean fewer search steps: the marginal is small, so it gets many.
inline constexpr int kEnvCdfRowCellsPerBin = 16, kEnvCdfColumnCellsPerBin = 2;
int envCdfGuideCells(int n, int cellsPerBin);
// Largest bin count per axis: guide cells store bin indices in 16 bits.
inline constexpr int kEnvCdfMaxBins = 65536;

// Builds the tables. Throws iblx::Error on an empty image, a negative or non-finite texel, or a side longer
// than kEnvCdfMaxBins.
EnvCdfData buildEnvCdf(const EnvImage& image);

// CPU twin of the env-cdf GLSL part: every step that touches the tables runs in float exactly as the GPU
// does, so sample() and pdf() return what the shader returns on the same u (up to the direction's
// trigonometry).
//
// Sampling, with u as the float the GPU receives (toGpuU):
//   y = (first k in 1..H with marginalCdf[k] > u.y) - 1, searched in [lo, hi] of guide cell u.y * G; rowProb
//   = marginalCdf[y+1] - marginalCdf[y]; t.y = (u.y - marginalCdf[y]) / rowProb, clamped to [0, 1 - 2^-24];
//   the same for x and t.x in row y's conditional (colProb); P = rowProb * colProb; direction =
//   texelToDirection(x, y, t); pdfSolidAngle = P / Omega_f(y), Omega_f = rowSolidAngles(W, H). Zero-width
//   bins are never chosen.
//
// Trade-offs (docs/DESIGN.md §4; Mitsuba 3's DiscreteDistribution2D, distr_2d.h):
// - Continuous in u.x within a row and affine inside each texel, but discontinuous in u.x at every row
//   boundary of u.y (each row has its own conditional): under QMC every row boundary becomes an edge in the
//   integrand, which pushes convergence towards the N^-1.5 "edges" regime (Mitchell 1996).
// - Float precision of globally normalised CDFs: near the top of a CDF the float spacing is 2^-24 ~ 6e-8,
//   comparable to a sky texel's share of a sun row. With rows accumulated in double and stored as float, the
//   worst bin's probability is off by 0.09 % at a sun of 1e3, 0.79 % at 1e4, 6.5 % at 1e5 and 50 % at 1e6
//   (for an 8192 x 4096 map); smaller shares round to zero-width bins that are never
//   sampled. The estimator stays unbiased wherever P > 0 because the pdf is the probability actually sampled
//   (a float CDF difference), never f/integral recomputed; zero-width texels are covered only through MIS.
// - Cost: two guide-table lookups, each followed by a binary search over the few bins of the cell (none when
//   the cell holds one bin), and one trigonometric direction. A cell spans many bins only where many bins
//   share 1/G of the probability, so the samples that need long searches are rare.
class EnvCdfSampler {
 public:
  // Keeps a copy of the tables. Throws iblx::Error when the array sizes do not match width and height.
  explicit EnvCdfSampler(EnvCdfData data);

  // Direction, its solid-angle pdf and its texel for u in [0,1)^2.
  EnvSample sample(glm::dvec2 u) const;
  // The same density for any direction: P(texel) / Omega_f(y) of the texel that contains wi.
  double pdf(glm::dvec3 wi) const;
  // u with sample(u).direction == wi (up to float rounding); empty when wi's texel has zero probability.
  std::optional<glm::dvec2> invert(glm::dvec3 wi) const;

  // Probability P (float) of texel (x, y), read from the tables exactly as sample() and pdf() do.
  float texelProbability(int x, int y) const;
  const EnvCdfData& data() const { return data_; }

 private:
  const float* conditionalRow(int y) const;
  const std::uint32_t* conditionalGuideRow(int y) const;

  EnvCdfData data_;
  std::vector<float> rowSolidAngles_;
};

// env-cdf's tables for shaders/env_technique/env_cdf.glsl: envCdf (the marginal, then every row's
// conditional) and envCdfGuide (the marginal's guide cells, then the rows'), with the guide sizes as
// definitions.
TechniqueData envCdfTechniqueData(const EnvImage& image);

}  // namespace iblx
