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

// GPU data of env-hier (a float array and a uvec4 array, plus rowSolidAngles(width, height)).
// Finest level: Pw x Ph, the next powers of two >= W and >= H; node (x, y) = image.weight(x, y) * Omega(y)
// for x < W, y < H, else 0 (padding). Level k+1 coarser than k has size max(w/2,1) x max(h/2,1), each node
// the sum of its 2 or 1 children per axis (sums in double, stored as float). An all-zero image uses Omega(y).
// levels[0] is the 1x1 root, levels.back() the finest level; nodes are laid out in the same order.
struct EnvHierData {
  int width = 0, height = 0;  // the environment map's W x H (the finest level may be larger: padding)
  std::vector<float> nodes;
  std::vector<EnvHierLevel> levels;
};

// Builds the pyramid. Throws iblx::Error on an empty image or a negative or non-finite texel.
EnvHierData buildEnvHier(const EnvImage& image);

// Where a descent may start for the u values of one guide cell: the deepest node whose preimage in u (a
// rectangle, since every split is along u.x or u.y) contains the whole cell. std430: vec4 + uvec4.
struct EnvHierStart {
  float minX = 0.0f, minY = 0.0f;          // the node's rectangle in u: [min, min + 1/invSize)
  float invSizeX = 1.0f, invSizeY = 1.0f;  // u_local = clamp((u - min) * invSize, 0, 1 - 2^-24), in float
  uint32_t node = 0;                       // heap index (below); >= leafStart for a texel
  uint32_t x = 0, y = 0;                   // the node's coordinates in its level
  float prob = 1.0f;                       // the float product of the shares on the path to it
};
static_assert(sizeof(EnvHierStart) == 32, "EnvHierStart is a std430 vec4 + uvec4");

// The layout shaders/env/env_hier.glsl reads.
//
// Nodes are numbered as a heap: level by level from the root, each level in Morton order (x on the even
// bits; the longer axis' extra high bits on top), so the children of a node are consecutive and found
// without any per-level table. With a = |log2 Pw - log2 Ph|, the first a levels split the longer axis only:
//   node g splitting one axis (g < oneAxisNodes = 2^a - 1): children 2g + 1 + c, c = cx + cy;
//   node g splitting both:                                children 4g + quadChildOffset + cx + 2 cy,
//                                                          quadChildOffset = 3 - 2^(a+1).
// shares[4g .. 4g+3] holds interior node g's split: (pLeft, pTop of the left column, pTop of the right
// column, 0), computed from its children q as texelProbability does (1 along an axis that does not split), so
// a step of the descent is one load and no division for the shares; nodes >= leafStart are the finest level
// (the texels), which need no record.
//
// The guide (guideSize^2 cells over u, row-major) lets the descent skip the levels every u of a cell shares:
// on the default map most samples start within two levels of their texel (EnvHierStart).
struct EnvHierGpuData {
  std::vector<float> shares;  // 4 floats per interior node
  std::vector<EnvHierStart> guide;
  uint32_t guideSize = 1;
  uint32_t levelCount = 1;  // levels including the root and the finest
  uint32_t oneAxisNodes = 0, leafStart = 0;
  int32_t quadChildOffset = 1;
  uint32_t finestWidth = 1, finestHeight = 1;  // Pw x Ph
};
// guideSize 0 picks min(256, max(Pw, Ph)).
EnvHierGpuData packEnvHierForGpu(const EnvHierData& data, uint32_t guideSize = 0);

// CPU twin of the env-hier GLSL part, step by step in float as the GPU computes it.
//
// sample(): u as the float the GPU receives (toGpuU) selects its guide cell min(floor(u * G), G - 1); the
// descent starts at that cell's node with u = clamp((u - min) * invSize, 0, 1 - 2^-24) and prob = its prob.
// In exact arithmetic this is the descent from the root (the guide only skips the levels the cell's u values
// share); in float the start differs by rounding, and pdf() (from the root) agrees with it to about 1e-6.
// The descent, from the root or from a start node: Going from level k to k+1, the
// children along x are {2x, 2x+1} if level k+1 is twice as wide, else {x}; the same along y. With q(i, j) the
// child values (i: column, j: row; a missing child counts as 0):
//   column: left = q(0,0) + q(0,1); right = q(1,0) + q(1,1); total = left + right (in this order);
//           pLeft = total > 0 ? left / total : 0.5;
//           u.x < pLeft ? (left,  u.x = u.x / pLeft,                prob *= pLeft)
//                       : (right, u.x = (u.x - pLeft) / (1 - pLeft), prob *= 1 - pLeft);
//   row, within the chosen column c: top = q(c,0); sum = top + q(c,1); pTop = sum > 0 ? top / sum : 0.5, and
//           the same choice with u.y;
//   each remapped u is clamped to [0, 1 - 2^-24].
// At the finest level, texel (x, y) and t = the remaining u give direction = texelToDirection(x, y, t) and
// pdfSolidAngle = prob / Omega_f(y), prob the float product of the chosen shares.
//
// Trade-offs (sampling_sota §1 and §6.1; Mitsuba 3 Hierarchical2D in distr_2d.h; Clarberg et al. 2005):
// - Robust in float: each level splits by a local ratio q0 / (q0 + q1), so the relative precision of every
//   share stays about 2^-24 per level, whatever the dynamic range; a sky texel next to a 1e6 sun keeps an
//   accurate probability where a globally normalised float CDF rounds it off (env-cdf). A share of exactly 0
//   is never chosen, and the 0.5 guard on an all-zero block is explicit.
// - Low distortion: a 2x2 block is split into halves of its own mass, so neighbourhoods in u stay compact
//   (good for Sobol / QMC), with no row-long shear around isolated peaks.
// - Discontinuous at every quadtree split (at all scales): a u crossing a split jumps between blocks.
// - Cost: one guide load, then the levels below the start node, one load each (on the default 256x128 sky a
//   sample starts 0.64 levels above its texel on average, and 3.5 for the slowest of 8 SIMD lanes, instead
//   of 8); padding to powers of two costs memory (< 4x); the guide costs 32 B per cell (2 MB at 256^2).
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

  // Probability prob (float) of texel (x, y): the product of the shares on its path, as sample() computes it.
  float texelProbability(int x, int y) const;
  const EnvHierData& data() const { return data_; }
  const EnvHierGpuData& gpuData() const { return gpu_; }

 private:
  // The children at level k+1 of node (x, y) at level k; q[i][j] = column i, row j (0 when missing).
  struct Children {
    bool splitX = false, splitY = false;
    glm::ivec2 first{0};  // coordinates of child (0, 0) at level k+1
    float q[2][2] = {{0.0f, 0.0f}, {0.0f, 0.0f}};
  };
  Children children(int level, glm::ivec2 node) const;

  EnvHierData data_;
  EnvHierGpuData gpu_;  // sample() walks the GPU layout, as the GLSL part does
  std::vector<float> rowSolidAngles_;
  std::vector<glm::ivec2> shift_;  // per level: log2(finest size / level size) along x and y
};

}  // namespace iblx
