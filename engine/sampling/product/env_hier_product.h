// env-hier product level: the data and CPU twin of the `product` strategies
// (shaders/lib/product_sampling.glsl), which sample the environment times the BRDF per shading point over
// env-hier's pyramid.
//
// Per shading point, every node j of one coarse pyramid level gets the weight
//   w_j = E_j ((1 - d) F_j / sum_k E_k F_k + d),
// E_j the node's env-hier probability (the area of its rectangle in u), F_j = mean_rgb(f) cos at the node's
// direction closest to the mirror direction of wo (the mirror direction itself when the node holds it), so a
// glossy lobe that touches a node is seen near its peak there, d = kEnvProductDefensive. A node is chosen by
// a marginal (rows) / conditional (columns) table over w, and the direction is finished inside the node by
// env-hier's own descent: the chosen node's rectangle R_j in u is filled by the remaining uniform, and
// env-hier's exact texel tables pick the texel. So
//   pdf(wi) = P(j) / E_j * p_env-hier(wi),   P(j) = w_j / sum_k w_k
// up to the table's 16-bit running sums (quantizedNodeProbabilities: the probabilities sampling follows),
// exact and evaluable at any direction (hierarchical product sampling, Clarberg, Jarosz, Akenine-Möller &
// Jensen 2005, "Wavelet Importance Sampling"; the conditional finish is the environment's exact warp, as in
// Clarberg & Akenine-Möller 2008 §4). The defensive share d keeps every node of positive env mass reachable
// (F_j is 0 for a node whose chosen direction is below the horizon, and a lobe not centred on the mirror
// direction can fall between the directions evaluated), so the estimator is unbiased whatever F does
// elsewhere in a node.
//
// The refinement (pyramid levels only) follows the lobe below a node's size: the kProductRefinedNodes nodes
// of largest E_j F_j are split into their four children on the next pyramid level, each valued
// e_c = E_c F_c at its own cap, and the kProductRefinedChildren children of largest e_c among those are split
// once more. A split node's (or child's) E F is replaced by the sum over its children (so its share of the
// table comes from the finer look), and a record keeps the children's conditional probabilities
// w_c = (1 - d) e_c / sum e + d E_c / sum E, quantized like the table. Sampling descends the records below
// the chosen node, choosing a child by the node's remaining u.x at the first split and u.y at the second, so
//   pdf(wi) = P(j) P(c | j) P(g | c) / E_leaf * p_env-hier(wi),
// E_leaf the area of the deepest node holding wi, whose rectangle in u is again exactly env-hier's preimage.
// The GPU refines a pixel's table only where the lobe falls below half its peak within one node's width of
// the mirror direction (productLobeNarrowerThanNode, two BRDF evaluations): elsewhere the split buys little
// (docs/RESULTS.md) and costs BRDF evaluations. Either way the sampler is exact; the twin's two constructors
// are the two outcomes.
#pragma once

#include "engine/sampling/env/env_hier.h"
#include "engine/sampling/piecewise_constant.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace iblx {

inline constexpr uint32_t kEnvProductMaxNodes = 512;
// 32-bit words of a pixel's stored table for a layout of width x rows nodes
// (shaders/lib/product_sampling.glsl): the rows' running sums, then each row's, quantized to 16 bits, two per
// word.
constexpr uint32_t productTableWords(uint32_t width, uint32_t rows) {
  return (rows + 1) / 2 + rows * ((width + 1) / 2);
}
// The refinement (pyramid levels): nodes split once (each gets a record; a node's slot + 1, 4 bits, marks it
// in the table, 0 when it is not split) and children split again, each with a record of its own.
inline constexpr uint32_t kProductRefinedNodes = 15, kProductRefinedChildren = 16;
inline constexpr uint32_t kProductMaxRefineDepth = 2;
// Words of a pixel's refinement block after its table: whether it has records (0 or 1), one 4-bit slot per
// node, then two words per record (the children's 16-bit running sums q_1, q_2, q_3; the mask of the
// children split again and the index of the first one's record).
constexpr uint32_t productRefineWords(uint32_t nodes) {
  return 1 + (nodes + 7) / 8 + 2 * (kProductRefinedNodes + kProductRefinedChildren);
}
// The largest over the layouts: a pyramid level has no more rows than nodes across (env-hier's square
// pyramid), so at most kEnvProductMaxNodes nodes give at most 32 x 16, as the uniform grid has; a pyramid
// level's refinement block follows.
inline constexpr uint32_t kEnvProductMaxTableWords =
    productTableWords(32, 16) + productRefineWords(kEnvProductMaxNodes);
inline constexpr double kEnvProductDefensive = 0.1;  // d: the env-hier share of every node's probability

// The nodes a product strategy chooses among, a partition of env-hier's unit square u into rectangles, in one
// of two layouts:
// - a pyramid level (`product`, `product-mis`): the finest level whose nodes that hold texels (width x rows)
//   number at most maxNodes; node (x, y) covers finest-level cells [x s, (x + 1) s) x [y s, (y + 1) s),
//   s = texelsPerNode, of which those inside the W x H map are texels. Its rectangle in u is where env-hier's
//   splits put it, so the nodes are regular in directions and their areas E_j follow the map.
// - a uniform grid over u (`product-warp`, warp composition: Hart, Pharr, Müller, Lopes, McGuire & Shirley
//   2020, "Practical Product Sampling by Fitting and Composing Warps"): node (x, y) is [x/width, (x+1)/width)
//   x [y/rows, (y+1)/rows), a piecewise-constant head warp over env-hier's square (the tail warp), so every
//   node carries the same env mass 1/(width rows) and the nodes are fine where the map is bright.
struct EnvProductLevel {
  uint32_t width = 0, rows = 0;
  uint32_t texelsPerNode = 0;  // pyramid level only
  bool uniformGrid = false;    // the layout: a uniform grid over u, else a pyramid level
  // Per node, row-major (rows x width): its rectangle in u (minX, minY, maxX, maxY), exactly the float set of
  // u whose env-hier descent ends in one of its texels (empty for padding).
  std::vector<glm::vec4> rects;
  // Per node: a unit direction (environment frame) at its centre, and in w the cosine of its angular radius
  // (the largest angle from the centre to a direction of the node, widened by a margin; -1 when the node's
  // directions spread over the sphere). A grid cell's cap is estimated from a 17 x 17 grid of u and can miss
  // a dim block thinner in u than its step. Only the weights read it, so a loose or short cap costs
  // efficiency, never bias.
  std::vector<glm::vec4> centers;
  std::size_t nodes() const { return rects.size(); }
};

// Throws iblx::Error when maxNodes is 0 or the pyramid is invalid.
EnvProductLevel buildEnvProductLevel(const EnvHierSampler& env, uint32_t maxNodes = kEnvProductMaxNodes);
// That level and the finer pyramid levels the refinement splits nodes into, at most maxDepth of them (fewer
// when the map has no finer level): levels[k] has 2^k times the nodes across of levels[0], node (x, y) of
// levels[k] having the children (2x + a, 2y + b) in levels[k + 1] (those of a row past the map are absent).
std::vector<EnvProductLevel> buildEnvProductLevels(const EnvHierSampler& env,
                                                   uint32_t maxNodes = kEnvProductMaxNodes,
                                                   uint32_t maxDepth = kProductMaxRefineDepth);
// The uniform grid over u; throws iblx::Error for an empty grid.
inline constexpr uint32_t kEnvProductGridWidth = 32, kEnvProductGridRows = 16;
EnvProductLevel buildEnvProductGrid(const EnvHierSampler& env, uint32_t width = kEnvProductGridWidth,
                                    uint32_t rows = kEnvProductGridRows);
// The uniform grid over the unit square of any tail warp (u -> direction); texelAngle, a texel's angular
// size, widens every cap (a cell's image holds whole texels' pieces). Throws iblx::Error for an empty grid.
EnvProductLevel buildEnvProductGrid(const std::function<glm::dvec3(glm::dvec2)>& tail, double texelAngle,
                                    uint32_t width, uint32_t rows);

// The node weights w_j = E_j ((1 - d) F_j / sum_k E_k F_k + d) (E_j alone when no node has a lobe value),
// E_j the area of node j's rectangle, F_j = fCos[j] clamped at 0. Throws iblx::Error when fCos has not one
// value per node.
std::vector<double> envProductWeights(const EnvProductLevel& level, std::span<const double> fCos);
// The table's 16-bit running sums, as the GPU stores them (shaders/lib/product_sampling.glsl): for weights
// w_1..w_n with running sums r_i and total W, of which m are positive,
//   q_i = min(round(r_i / W (65535 - m)), 65535 - m) + (the positive weights among w_1..w_i),
// so every positive weight keeps at least one of the 65535 steps and q_n = 65535 (all 0 when W = 0).
// Throws iblx::Error for a negative or non-finite weight.
inline constexpr uint32_t kProductFullScale = 65535;
std::vector<uint32_t> quantizedRunningSums(std::span<const double> weights);
// P(j) of the quantized table over the level's nodes: (the row's step) / 65535 * (the node's step in its row)
// / 65535, from the rows' totals and each row's weights; all 0 when every weight is. The sampler's choice and
// its pdf both read these, as the GPU's do.
std::vector<double> quantizedNodeProbabilities(const EnvProductLevel& level, std::span<const double> weights);
// The point of node j's rectangle in u where the head table's choice `chosen` (a sample of the level's
// width x rows table) puts u: its place in the table's cell, mapped into the rectangle (a float set: one
// float step below its upper edges at most), as the GPU computes it.
glm::dvec2 pointInProductNode(const PiecewiseConstant2D::Sample& chosen, const EnvProductLevel& level,
                              std::size_t j);

// The direction of the cap (centre, cosRadius) closest to `towards` (unit vectors): `towards` itself inside
// the cap, else the centre turned towards it by the radius. The GLSL twin is productNodeDirection.
glm::dvec3 closestDirectionInCap(glm::dvec3 centre, double cosRadius, glm::dvec3 towards);

// F of a node from its cap (centre xyz, cosine of the radius in w): the GPU evaluates mean_rgb(f) cos at the
// cap's direction closest to the mirror direction of wo (closestDirectionInCap).
using ProductCapLobe = std::function<double(const glm::vec4& cap)>;

// The product's choice of the deepest node holding a direction: its depth in the levels, its row-major index
// there, and its probability P(j) P(c | j) ... .
struct ProductLeaf {
  uint32_t depth = 0;
  std::size_t node = 0;
  double probability = 0.0;
};

// CPU twin of the GLSL sampler for one shading point, in double.
class EnvProductSampler {
 public:
  // One level, no refinement: fCos[j] = F_j (>= 0) of node j.
  EnvProductSampler(const EnvHierSampler& env, const EnvProductLevel& level, std::span<const double> fCos);
  // Refined over `levels` (buildEnvProductLevels, kept alive by the caller), F of every node from `lobe`.
  EnvProductSampler(const EnvHierSampler& env, std::span<const EnvProductLevel> levels,
                    const ProductCapLobe& lobe);

  // Chooses a node by u.y (row) and u.x (column), rescales u inside the choice, descends the node's records
  // (u.x, then u.y), fills the deepest node's rectangle with what is left of u and lets env-hier's descent
  // finish.
  EnvSample sample(glm::dvec2 u) const;
  double pdf(glm::dvec3 wi) const;
  // P(j) of the quantized table (quantizedNodeProbabilities), which the choice follows exactly.
  double nodeProbability(std::size_t node) const { return tables_.probability[node]; }
  // The node holding direction wi: by its texel (pyramid level) or by env-hier's inverse (uniform grid).
  std::size_t nodeOf(glm::dvec3 wi) const;
  // The deepest node holding a direction that lies in a texel of positive env-hier probability.
  ProductLeaf leafOf(glm::dvec3 wi) const;
  // The nodes split once (in order of E F, largest first) and the children split again (row-major indices
  // in levels[1]).
  const std::vector<std::size_t>& refinedNodes() const { return tables_.refinedNodes; }
  const std::vector<std::size_t>& refinedChildren() const { return tables_.refinedChildren; }

 private:
  // A split node's children: their quantized running sums, and each child's own record (-1: not split).
  struct Record {
    std::vector<uint32_t> sums;
    int childRecord[4] = {-1, -1, -1, -1};
  };
  // What the constructors compute before the table's choice is built.
  struct Tables {
    std::vector<double> probability;  // P(j)
    std::vector<int> recordOfNode;    // per node of levels[0]: its record, -1 when not split
    std::vector<Record> records;
    std::vector<std::size_t> refinedNodes, refinedChildren;
  };
  EnvProductSampler(const EnvHierSampler& env, std::span<const EnvProductLevel> levels, Tables tables);
  static Tables refinedTables(std::span<const EnvProductLevel> levels, const ProductCapLobe& lobe);

  const EnvHierSampler& env_;
  std::span<const EnvProductLevel> levels_;
  Tables tables_;
  PiecewiseConstant2D nodes_;  // the row/column choice over P(j)
};

// The product strategies' tables (shaders/lib/product_sampling.glsl) after env-hier's, from the same pyramid:
// productNodeRects and productNodeCenters of the level `product` and `product-mis` choose nodes on, and
// productGridCenters, the caps of `product-warp`'s uniform grid over u (its rectangles are arithmetic). The
// first two go on with the refinement's finer levels ordered by parent (N + 4 j + c for child c of node j,
// 5 N + 16 j + 4 c + g for its grandchild g), PRODUCT_REFINE_DEPTH of them (0 to 2).
TechniqueData envHierProductTechniqueData(const EnvImage& image);

}  // namespace iblx
