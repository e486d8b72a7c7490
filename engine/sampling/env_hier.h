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

// The layout shaders/env/env_hier.glsl reads: for every level but the finest, one vec4 per node holding its
// children (q(0,0), q(1,0), q(0,1), q(1,1)), 0 where missing, so each step of the descent is one load.
// Level info: x = offset (in vec4s), y = width, z = height, w = splitX | splitY << 1 | shiftX << 8 | shiftY
// << 16 (shift = the number of x / y doublings from this level's children down to the finest level).
struct EnvHierGpuData {
  std::vector<float> children;  // 4 floats per node
  std::vector<EnvHierLevel> levels;
};
EnvHierGpuData packEnvHierForGpu(const EnvHierData& data);

// CPU twin of the env-hier GLSL part, step by step in float as the GPU computes it.
//
// Descent from the root, with u as the float the GPU receives (toGpuU). Going from level k to k+1, the
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
// - Cost: log2(max(Pw, Ph)) levels of 4 dependent loads; padding to powers of two costs memory (< 4x).
class EnvHierSampler {
 public:
  // Keeps a copy of the pyramid. Throws iblx::Error when the levels do not describe a valid pyramid.
  explicit EnvHierSampler(EnvHierData data);

  EnvSample sample(glm::dvec2 u) const;
  // The same density for any direction: the product of the shares on the path to wi's texel / Omega_f(y).
  double pdf(glm::dvec3 wi) const;
  // u with sample(u).direction == wi (up to float rounding); empty when a share on the path is 0.
  std::optional<glm::dvec2> invert(glm::dvec3 wi) const;

  // Probability prob (float) of texel (x, y): the product of the shares on its path, as sample() computes it.
  float texelProbability(int x, int y) const;
  const EnvHierData& data() const { return data_; }

 private:
  // The children at level k+1 of node (x, y) at level k; q[i][j] = column i, row j (0 when missing).
  struct Children {
    bool splitX = false, splitY = false;
    glm::ivec2 first{0};  // coordinates of child (0, 0) at level k+1
    float q[2][2] = {{0.0f, 0.0f}, {0.0f, 0.0f}};
  };
  Children children(int level, glm::ivec2 node) const;

  EnvHierData data_;
  std::vector<float> rowSolidAngles_;
  std::vector<glm::ivec2> shift_;  // per level: log2(finest size / level size) along x and y
};

}  // namespace iblx
