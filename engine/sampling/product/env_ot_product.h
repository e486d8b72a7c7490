// Warp composition over env-ot's unit square: the data and CPU twin of `product-warp-ot`
// (shaders/lib/product_sampling.glsl with PRODUCT_TAIL_ENV_OT, shaders/lib/env_ot_inverse.glsl).
//
// Hart, Pharr, Müller, Lopes, McGuire & Shirley 2020, "Practical Product Sampling by Fitting and Composing
// Warps" (EGSR), §5: a head warp, per shading point a piecewise-constant table of f cos over a uniform grid
// of the tail's unit square, is composed with the tail, here env-ot (engine/sampling/env/env_ot.h). The
// head's cells carry the weights of engine/sampling/product/env_hier_product.h (w_j = E_j ((1 - d) F_j /
// sum_k E_k F_k + d), E_j = the cell's area), so the head density at u is h(u) = P(cell of u) / E(cell of u).
//
// env-ot's warp is not injective when its sun is split: a sun texel is reached from the map's rows (pieces
// of the OT grid) and from the sun row (the whole texel, its excess weight). Each branch is uniform in solid
// angle over the texel, with densities q_map (the texel's probability through the map's pieces over its solid
// angle Omega) and q_sun (through the sun row), q_map + q_sun = env-ot's pdf. The composed density sums over
// the preimages:
//   p(wi) = h(u_map) q_map(wi) + h(u_sun) q_sun(wi),
// u_b = the branch's inverse of wi; elsewhere (one preimage) p(wi) = h(u) p_env-ot(wi). Sampling draws the
// head cell, fills it with the rescaled u, and lets env-ot's warp finish; the sample's pdf takes the branch
// it went through from the chosen u and locates the other preimage only on a sun texel.
//
// Trade-offs against `product-warp` (env-hier's tail): the inverse is a search over the texel's pieces (a
// barycentric test per triangle) instead of one rectangle read, and the inverse tables add 8 B per piece and
// 12 B per texel; env-ot's sample costs more than env-hier's and its warp jumps between pieces inside a cell,
// which flattens the convergence under low-discrepancy points. With independent points its variance per
// sample is close to `product-warp`'s; at equal time with sobol it loses several times over, to the cost per
// sample and the flatter slope (docs/BENCHMARKS.md, "Warp composition on the OT square").
#pragma once

#include "engine/io/env_image.h"
#include "engine/sampling/env/env_ot.h"
#include "engine/sampling/product/env_hier_product.h"
#include "engine/sampling/piecewise_constant.h"
#include "engine/sampling/technique_data.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace iblx {

// env-ot's inverse, as the GLSL reads it.
struct EnvOtInverse {
  int width = 0, height = 0, grid = 0;
  // W*H + 1: texel t's entries are [texelFirst[t], texelFirst[t + 1]).
  std::vector<std::uint32_t> texelFirst;
  // Per entry (piece, row): the texel's map pieces of positive probability (rows < grid), then its sun-row
  // piece (row == grid) when it has one.
  std::vector<glm::uvec2> entries;
  // Per texel (q_map, q_sun): the branch densities w.r.t. solid angle (q_map = env-ot's texelPdf where the
  // texel has no sun piece).
  std::vector<glm::vec2> branchPdf;
};

// Throws iblx::Error when the tables disagree with the map's size.
EnvOtInverse buildEnvOtInverse(const EnvOtData& data);

// The preimages of a direction under env-ot's warp, one per branch (empty where the branch does not reach
// wi's texel), from the same float steps as the GLSL (envOtInvertMap / envOtInvertSun) in double.
struct EnvOtPreimages {
  std::optional<glm::dvec2> map, sun;
  double mapPdf = 0.0, sunPdf = 0.0;  // q_map, q_sun
};
EnvOtPreimages envOtPreimages(const EnvOtData& data, const EnvOtInverse& inverse, glm::dvec3 wi);

// CPU twin of the composed sampler for one shading point: fCos[j] = F_j (>= 0) of head cell j.
class EnvOtProductSampler {
 public:
  // Keeps references: env, inverse and grid must outlive the sampler. Throws iblx::Error when fCos has not
  // one value per cell or the grid is not a uniform grid.
  EnvOtProductSampler(const EnvOtSampler& env, const EnvOtInverse& inverse, const EnvProductLevel& grid,
                      std::span<const double> fCos);

  EnvSample sample(glm::dvec2 u) const;
  double pdf(glm::dvec3 wi) const;
  // h(u) = P(cell of u) / E(cell of u).
  double headDensity(glm::dvec2 u) const;
  double cellProbability(std::size_t cell) const { return probability_[cell]; }

 private:
  std::size_t cellOf(glm::dvec2 u) const;
  // h(u_map) q_map + h(u_sun) q_sun at wi; `taken` (a branch's u and its head density) replaces the located
  // preimage of that branch.
  double composedPdf(glm::dvec3 wi, std::optional<std::pair<bool, double>> taken) const;

  const EnvOtSampler& env_;
  const EnvOtInverse& inverse_;
  const EnvProductLevel& grid_;
  std::vector<double> probability_;  // P(j)
  PiecewiseConstant2D cells_;        // the row/column choice over the weights
};

// env-ot's tables (envOtTechniqueData), the inverse's (envOtTexelEntryFirst, envOtTexelEntry,
// envOtBranchPdf) and the head grid's caps (productGridCenters), with PRODUCT_GRID_WIDTH, PRODUCT_GRID_ROWS,
// PRODUCT_DEFENSIVE, ENV_OT_GRID and PRODUCT_TAIL_ENV_OT, which selects the env-ot tail in
// shaders/lib/product_sampling.glsl.
TechniqueData envOtProductTechniqueData(const EnvImage& image);
TechniqueData envOtProductTechniqueData(const EnvOtData& data);
// The head grid over env-ot's unit square (buildEnvProductGrid with env-ot's warp for the tail).
EnvProductLevel buildEnvOtProductGrid(const EnvOtSampler& env, uint32_t width = kEnvProductGridWidth,
                                      uint32_t rows = kEnvProductGridRows);

}  // namespace iblx
