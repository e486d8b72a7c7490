// env-hier: hierarchical 2x2 mip-pyramid warp over the texels of a lat-long map (builder + CPU twin of
// shaders/env/env_hier.glsl).
#pragma once

#include "engine/io/env_image.h"
#include "engine/sampling/latlong_texel.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace iblx {

// One pyramid level, std430 uvec4: its nodes are nodes[offset + y*width + x], row-major.
struct EnvHierLevel {
  uint32_t offset = 0, width = 0, height = 0, pad = 0;
};
static_assert(sizeof(EnvHierLevel) == 16, "EnvHierLevel is a std430 uvec4");

// The pyramid of env-hier. Finest level: S x S, S the next power of two >= max(W, H); node (x, y) =
// image.weight(x, y) * Omega(y) for x < W, y < H, else 0 (padding). Level k+1 coarser than k has size
// (w/2) x (h/2), each node the sum of its 2 x 2 children (sums in double, stored as float). An all-zero image
// uses Omega(y). levels[0] is the 1x1 root, levels.back() the finest level; nodes are laid out in the same
// order. Padding a 2:1 map to a square adds one split at the root whose second row is empty (pTop = 1), so
// the warp is the same as a pyramid of 2:1 levels; every level splitting both axes keeps the GPU's child
// index one formula.
struct EnvHierData {
  int width = 0, height = 0;  // the environment map's W x H (the finest level is larger: padding)
  std::vector<float> nodes;
  std::vector<EnvHierLevel> levels;
};

// Builds the pyramid. Throws iblx::Error on an empty image or a negative or non-finite texel.
EnvHierData buildEnvHier(const EnvImage& image);

// The layout shaders/env/env_hier.glsl reads.
//
// Nodes are numbered as a heap: level by level from the root, each level in Morton order (x on the even
// bits), so node g's children are 4g + 1 + cx + 2 cy, found without any per-level table. shares[4g .. 4g+3]
// holds interior node g's split: (pLeft, pTop of the left column, pTop of the right column, 0), computed from
// its children q as the descent uses them, so a step of the descent is one load and no division for the
// shares; nodes >= leafStart are the finest level (the texels), which need no record.
//
// texelProbability[y * W + x] is the probability of texel (x, y): the float product of the shares on its
// path (column before row at each level, root first). The descent reads it at its texel instead of
// multiplying shares, and pdf() of any direction is the same single read, so both agree bit for bit.
//
// The guide (guideSize^2 cells over u, row-major) lets the descent skip the levels every u of a cell shares:
// per cell the deepest node whose preimage in u (a rectangle, since every split is along u.x or u.y)
// contains the whole cell, as its heap index (guideNodes) and its rectangle (guideRects: the lower corner
// min, then 1 / size, so that u_local = clamp((u - min) * invSize, 0, 1 - 2^-24) in float).
struct EnvHierGpuData {
  std::vector<float> shares;  // 4 floats per interior node
  std::vector<float> texelProbability;
  std::vector<glm::vec4> guideRects;  // (minX, minY, invSizeX, invSizeY) per cell
  std::vector<uint32_t> guideNodes;   // heap index per cell; >= leafStart for a texel
  uint32_t guideSize = 1;
  uint32_t leafStart = 0;
};
// guideSize 0 picks min(kEnvHierGuideSize, S). Throws iblx::Error when guideSize is not a power of two or
// the levels are not square.
inline constexpr uint32_t kEnvHierGuideSize = 256;
EnvHierGpuData packEnvHierForGpu(const EnvHierData& data, uint32_t guideSize = 0);

// CPU twin of the env-hier GLSL part, step by step in float as the GPU computes it.
//
// sample(): u as the float the GPU receives (toGpuU) selects its guide cell min(floor(u * G), G - 1); the
// descent starts at that cell's node with u = clamp((u - min) * invSize, 0, 1 - 2^-24). In exact arithmetic
// this is the descent from the root (the guide only skips the levels the cell's u values share); in float the
// start differs by rounding. Going from level k to k+1, the children of node (x, y) are {2x, 2x+1} x
// {2y, 2y+1}. With q(i, j) the child values (i: column, j: row):
//   column: left = q(0,0) + q(0,1); right = q(1,0) + q(1,1); total = left + right (in this order);
//           pLeft = total > 0 ? left / total : 0.5;
//           u.x < pLeft ? (left,  u.x = u.x / pLeft)
//                       : (right, u.x = (u.x - pLeft) / (1 - pLeft));
//   row, within the chosen column c: top = q(c,0); sum = top + q(c,1); pTop = sum > 0 ? top / sum : 0.5, and
//           the same choice with u.y;
//   each remapped u is clamped to at most 1 - 2^-24 (it is never negative, and the share taken is never 0: a
//   share of 0 would need u < 0 or u >= 1).
// At the finest level, texel (x, y) and t = the remaining u give direction = texelToDirection(x, y, t) and
// pdfSolidAngle = texelProbability(x, y) / Omega_f(y).
//
// Trade-offs (sampling_sota §1 and §6.1; Mitsuba 3 Hierarchical2D in distr_2d.h; Clarberg et al. 2005):
// - Robust in float: each level splits by a local ratio q0 / (q0 + q1), so the relative precision of every
//   share stays about 2^-24 per level, whatever the dynamic range; a sky texel next to a 1e6 sun keeps an
//   accurate probability where a globally normalised float CDF rounds it off (env-cdf). A share of exactly 0
//   is never chosen, and the 0.5 guard on an all-zero block is explicit.
// - Low distortion: a 2x2 block is split into halves of its own mass, so neighbourhoods in u stay compact
//   (good for Sobol / QMC), with no row-long shear around isolated peaks.
// - Discontinuous at every quadtree split (at all scales): a u crossing a split jumps between blocks.
// - Cost: one guide load (two tables), then the levels below the start node, one load each, and one load of
//   the texel's probability; pdf() is one load. On SIMD hardware the slowest lane sets the pace: on the
//   default 256x128 sky, the slowest of 8 lanes walks about 3.5 levels below a 256^2 guide's start.
//   Memory: the shares take 16 B per interior node, about 11 B per texel of a 2:1 map (padding it to a
//   square doubles them), the texel probabilities 4 B per texel, the guide 20 B per cell (1.3 MB at 256^2).
class EnvHierSampler {
 public:
  // Keeps a copy of the pyramid and packs it as the GPU reads it (guideSize as in packEnvHierForGpu).
  // Throws iblx::Error when the levels do not describe a valid pyramid.
  explicit EnvHierSampler(EnvHierData data, uint32_t guideSize = 0);

  EnvSample sample(glm::dvec2 u) const;
  // The same density for any direction: the product of the shares on the path to wi's texel / Omega_f(y).
  double pdf(glm::dvec3 wi) const;
  // u with sample(u).direction == wi (up to float rounding); empty when a share on the path is 0.
  std::optional<glm::dvec2> invert(glm::dvec3 wi) const;

  // Probability (float) of texel (x, y): the product of the shares on its path (EnvHierGpuData).
  float texelProbability(int x, int y) const;
  const EnvHierData& data() const { return data_; }
  const EnvHierGpuData& gpuData() const { return gpu_; }

 private:
  EnvHierData data_;
  EnvHierGpuData gpu_;  // sample() walks the GPU layout, as the GLSL part does
  std::vector<float> rowSolidAngles_;
};

}  // namespace iblx
