// env-hier: hierarchical 2x2 mip-pyramid warp over the texels of a lat-long map (builder + CPU twin of
// shaders/env_technique/env_hier.glsl).
#pragma once

#include "engine/io/env_image.h"
#include "engine/io/latlong_texel.h"
#include "engine/sampling/technique_data.h"

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

// The layout shaders/env_technique/env_hier.glsl reads.
//
// Every node covers a rectangle of u, [lo, hi) per axis, with float corners: the root [0, 1)^2; a node splits
// its rectangle at x = splitX into columns, and each column at its own y (splitYLeft, splitYRight) into rows,
// each split where the children's masses put it (splitPoint in env_hier.cpp, from the child sums in double,
// rounded to float once). The descent compares u with the stored splits: u.x >= splitX picks the right
// column, then u.y >= that column's split the lower row. No u is remapped on the way, so the CPU twin and the
// GPU take the same path bit for bit, and a texel is chosen exactly when u lies in its rectangle: the
// probability of texel t is the area of its rectangle, sizeX * sizeY in float, which is what sample() and
// pdf() return. A child of zero mass has an empty rectangle (never chosen, probability 0); a child of
// positive mass keeps at least one float step of width wherever its parent has two.
//
// Nodes are numbered as a heap: level by level from the root, each level in Morton order (x on the even
// bits), so node g's children are 4g + 1 + cx + 2 cy, found without any per-level table. splits[g] holds
// interior node g's (splitX, splitYLeft, splitYRight, 0); nodes from leafStart on are the finest level (the
// texels, in Morton order), which need no record.
//
// texelRects[y * W + x] is texel (x, y)'s rectangle (minX, minY, sizeX, sizeY): the descent reads it once to
// place the direction inside the texel, t = (u - min) / size, and pdf() reads it for the probability.
//
// The guide (guideSize^2 cells over u, row-major) lets the descent skip the levels every u of a cell shares:
// per cell the heap index of the deepest node whose rectangle contains the whole cell. Since the rectangles
// are exact float sets, starting there gives the same texel as starting at the root.
struct EnvHierGpuData {
  std::vector<glm::vec4> splits;      // per interior node
  std::vector<glm::vec4> texelRects;  // per texel: (minX, minY, sizeX, sizeY)
  std::vector<uint32_t> guideNodes;   // heap index per cell; >= leafStart for a texel
  uint32_t guideSize = 1;
  uint32_t leafStart = 0;
};
// guideSize 0 picks min(kEnvHierGuideSize, S). Throws iblx::Error when guideSize is not a power of two or
// the levels are not square.
inline constexpr uint32_t kEnvHierGuideSize = 128;
EnvHierGpuData packEnvHierForGpu(const EnvHierData& data, uint32_t guideSize = 0);

// The rectangle in u (minX, minY, maxX, maxY) of node (x, y) of pyramid level `level` (2^level nodes across):
// exactly the float set of u whose descent passes through the node, found by walking the splits from the
// root. The level must be coarser than the finest one's parent's children, i.e. level <= the finest level.
glm::vec4 envHierNodeRect(const EnvHierGpuData& gpu, uint32_t level, uint32_t x, uint32_t y);

// CPU twin of the env-hier GLSL part, step by step in float as the GPU computes it.
//
// sample(): u as the float the GPU receives (toGpuU) selects its guide cell min(floor(u * G), G - 1); from
// that cell's node the descent goes down by comparisons with the splits (EnvHierGpuData) to texel (x, y).
// There, t = clamp((u - min) / size, 0, 1 - 2^-24) gives direction = texelToDirection(x, y, t), and
// pdfSolidAngle = sizeX * sizeY / Omega_f(y).
//
// Trade-offs (Mitsuba 3's Hierarchical2D, distr_2d.h; Clarberg et al. 2005):
// - Each level splits by the local ratio q0 / (q0 + q1), computed in double from the child sums; the split is
//   placed in u with float precision (2^-24 near 1, finer towards 0). A u is itself a float on a 2^-24 grid,
//   so no warp can resolve finer than that; here the reported probability is the area of exactly the set of u
//   that reach the texel, so pdf and sampling agree even for texels a few grid steps wide. A texel of
//   positive weight loses its rectangle only where its parent is one float step wide (its mass then goes to
//   its sibling, and MIS still sees pdf 0 there, consistently).
// - Low distortion: a 2x2 block is split into halves of its own mass, so neighbourhoods in u stay compact
//   (good for Sobol / QMC), with no row-long shear around isolated peaks.
// - Discontinuous at every quadtree split (at all scales): a u crossing a split jumps between blocks.
// - Cost: one guide load, then one load and two comparisons per level below the start node, and one load of
//   the texel's rectangle; pdf() is one load. On SIMD hardware the slowest lane sets the pace: on the
//   default 256x128 sky, the slowest of 8 lanes walks about 3.5 levels below a 256^2 guide's start. The
//   guide is 128^2 by default: a finer guide starts the descent lower, but on lavapipe the levels a 256^2
//   guide saves did not show in the time, and from 512^2 (1 MB) on the guide's cache misses cost more than
//   the levels it saves (docs/BENCHMARKS.md, "What was tried for speed").
//   Memory: 16 B per interior node (about 11 B per texel of a 2:1 map: padding it to a square doubles them),
//   16 B per texel for the rectangles, 4 B per guide cell (64 KB at 128^2).
class EnvHierSampler {
 public:
  // Keeps a copy of the pyramid and packs it as the GPU reads it (guideSize as in packEnvHierForGpu).
  // Throws iblx::Error when the levels do not describe a valid pyramid.
  explicit EnvHierSampler(EnvHierData data, uint32_t guideSize = 0);

  EnvSample sample(glm::dvec2 u) const;
  // The same density for any direction: the product of the shares on the path to wi's texel / Omega_f(y).
  double pdf(glm::dvec3 wi) const;
  // u with sample(u).direction == wi (up to float rounding); empty when the texel's rectangle is empty.
  std::optional<glm::dvec2> invert(glm::dvec3 wi) const;

  // Probability (float) of texel (x, y): the area of its rectangle in u (EnvHierGpuData).
  float texelProbability(int x, int y) const;
  const EnvHierData& data() const { return data_; }
  const EnvHierGpuData& gpuData() const { return gpu_; }

 private:
  const glm::vec4& texelRect(int x, int y) const;  // gpu_.texelRects of texel (x, y)

  EnvHierData data_;
  EnvHierGpuData gpu_;  // sample() walks the GPU layout, as the GLSL part does
  std::vector<float> rowSolidAngles_;
};

// env-hier's tables for shaders/env_technique/env_hier.glsl (hierSplits, hierGuide, hierTexelRects) from its
// pyramid, with its sizes as definitions (read from a buffer, lavapipe would load them per lane).
TechniqueData envHierTechniqueData(const EnvHierSampler& sampler);
TechniqueData envHierTechniqueData(const EnvImage& image);

}  // namespace iblx
