// env-hier: mip-pyramid builder (double sums, float storage) and the float-exact CPU twin of the GLSL warp.
#include "engine/sampling/env/env_hier.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <bit>
#include <limits>
#include <string>
#include <utility>

namespace iblx {
namespace {

// Where a node's rectangle [lo, hi) splits along one axis for a first child of `share` of its mass, rounded
// to float once: lo for share 0 and hi for share 1 exactly (the empty child is never chosen); otherwise
// strictly inside whenever [lo, hi) holds two float steps, so a child of positive mass stays reachable.
float splitPoint(float lo, float hi, double share) {
  if (!(share > 0.0)) return lo;
  if (!(share < 1.0)) return hi;
  float split = float(double(lo) + share * (double(hi) - double(lo)));
  if (split <= lo) split = std::nextafter(lo, hi);
  if (split >= hi) split = std::nextafter(hi, lo);
  return std::clamp(split, lo, hi);
}

// Share of the first of two child masses; 0.5 for an empty pair (never reached: its parent's share is 0).
double firstShare(double first, double second) {
  const double total = first + second;
  return total > 0.0 ? first / total : 0.5;
}

// Morton index of node (x, y) of a square level: x on the even bits, y on the odd bits.
uint64_t mortonIndex(uint32_t x, uint32_t y) {
  uint64_t m = 0;
  for (int b = 0; b < 32; ++b)
    m |= (uint64_t((x >> b) & 1u) << (2 * b)) | (uint64_t((y >> b) & 1u) << (2 * b + 1));
  return m;
}

// The even bits of m, compacted: mortonIndex's inverse along one axis.
uint32_t mortonAxis(uint64_t m) {
  uint32_t v = 0;
  for (int b = 0; b < 32; ++b) v |= uint32_t((m >> (2 * b)) & 1u) << b;
  return v;
}

// Heap index of the child (cx, cy) of node g (EnvHierGpuData).
uint32_t hierChild(uint32_t g, uint32_t cx, uint32_t cy) {
  return 4u * g + 1u + cx + 2u * cy;
}

// Rectangle (lo.x, lo.y, hi.x, hi.y) of child (column, row) of a node with rectangle `rect` and splits
// (splitX, splitY of the left column, splitY of the right column).
glm::vec4 childRect(glm::vec4 rect, glm::vec4 split, uint32_t column, uint32_t row) {
  const float splitY = column == 0 ? split.y : split.z;
  return {column == 0 ? rect.x : split.x, row == 0 ? rect.y : splitY, column == 0 ? split.x : rect.z,
          row == 0 ? splitY : rect.w};
}

// Level k is 2^k x 2^k, as buildEnvHier makes them.
bool hasSquareLevels(const std::vector<EnvHierLevel>& levels) {
  for (std::size_t k = 0; k < levels.size(); ++k)
    if (k >= 32 || levels[k].width != (1u << k) || levels[k].height != (1u << k)) return false;
  return true;
}

}  // namespace

EnvHierData buildEnvHier(const EnvImage& image) {
  std::vector<double> weights = texelSamplingWeights(image, "env-hier");
  const int width = image.width, height = image.height;
  if (width > (1 << 28) || height > (1 << 28))
    throw Error("env-hier: a " + std::to_string(width) + " x " + std::to_string(height) +
                " map is too large for the pyramid; downsample it");

  // Finest level S x S: the texel weights, zero padding beyond W x H.
  int size = int(std::max(std::bit_ceil(unsigned(width)), std::bit_ceil(unsigned(height))));
  std::vector<double> level;
  if (size == width && size == height) {
    level = std::move(weights);
  } else {
    level.assign(std::size_t(size) * std::size_t(size), 0.0);
    for (int y = 0; y < height; ++y)
      std::copy_n(weights.begin() + std::ptrdiff_t(image.index(0, y)), width,
                  level.begin() + std::ptrdiff_t(y) * size);
    weights = {};
  }

  // Coarser levels: each node is the sum (in double) of its 2 x 2 children. Only the current level is kept
  // in double; every level is stored as float, finest first while building.
  std::vector<std::vector<float>> stored;
  std::vector<int> sizes;
  const auto store = [&] {
    stored.emplace_back(level.begin(), level.end());
    sizes.push_back(size);
  };
  store();
  while (size > 1) {
    const int coarse = size / 2;
    std::vector<double> sums(std::size_t(coarse) * std::size_t(coarse), 0.0);
    for (int y = 0; y < coarse; ++y)
      for (int x = 0; x < coarse; ++x) {
        const std::size_t top = std::size_t(2 * y) * std::size_t(size) + std::size_t(2 * x);
        sums[std::size_t(y) * std::size_t(coarse) + std::size_t(x)] =
            level[top] + level[top + 1] + level[top + std::size_t(size)] + level[top + std::size_t(size) + 1];
      }
    level = std::move(sums);
    size = coarse;
    store();
  }
  if (!(level[0] <= double(std::numeric_limits<float>::max())))
    throw Error("env-hier: the total sampling weight overflows float; scale the environment map down");

  // Store coarsest first: levels[0] is the root, nodes in the same order.
  EnvHierData data;
  data.width = width;
  data.height = height;
  std::size_t offset = 0;
  for (std::size_t k = stored.size(); k-- > 0;) {
    data.levels.push_back({uint32_t(offset), uint32_t(sizes[k]), uint32_t(sizes[k]), 0u});
    offset += stored[k].size();
  }
  if (offset > std::numeric_limits<uint32_t>::max())
    throw Error("env-hier: the pyramid needs more than 2^32 nodes; downsample the environment map");
  data.nodes.reserve(offset);
  for (std::size_t k = stored.size(); k-- > 0;) {
    data.nodes.insert(data.nodes.end(), stored[k].begin(), stored[k].end());
    stored[k] = {};
  }
  return data;
}

EnvHierSampler::EnvHierSampler(EnvHierData data, uint32_t guideSize) : data_(std::move(data)) {
  const auto fail = [](const std::string& why) {
    throw Error("env-hier: invalid pyramid (" + why + "); rebuild it with buildEnvHier");
  };
  const auto& levels = data_.levels;
  if (data_.width <= 0 || data_.height <= 0 || levels.empty()) fail("empty");
  if (!hasSquareLevels(levels)) fail("level sizes are not 1, 2, 4, ... squared");
  std::size_t offset = 0;
  for (const EnvHierLevel& l : levels) {
    if (l.offset != offset) fail("levels are not consecutive");
    offset += std::size_t(l.width) * l.height;
  }
  if (offset != data_.nodes.size()) fail("node count does not match the levels");
  const EnvHierLevel& finest = levels.back();
  if (int(finest.width) < data_.width || int(finest.height) < data_.height) fail("finest level too small");
  rowSolidAngles_ = rowSolidAngles(data_.width, data_.height);
  gpu_ = packEnvHierForGpu(data_, guideSize);
}

EnvSample EnvHierSampler::sample(glm::dvec2 u) const {
  const float ux = toGpuU(u.x), uy = toGpuU(u.y);
  // u * G is exact (G a power of two) and < G for u < 1.
  const uint32_t g = gpu_.guideSize;
  uint32_t node = gpu_.guideNodes[std::size_t(std::min(uint32_t(uy * float(g)), g - 1u)) * g +
                                  std::min(uint32_t(ux * float(g)), g - 1u)];
  while (node < gpu_.leafStart) {
    const glm::vec4& split = gpu_.splits[node];
    const uint32_t column = ux >= split.x ? 1u : 0u;  // column first, then the row inside it
    const uint32_t row = uy >= (column == 0 ? split.y : split.z) ? 1u : 0u;
    node = hierChild(node, column, row);
  }
  const uint64_t m = node - gpu_.leafStart;
  const glm::ivec2 n(int(mortonAxis(m)), int(mortonAxis(m >> 1)));
  EnvSample s;
  if (n.x >= data_.width || n.y >= data_.height) {  // padding: unreachable (its rectangles are empty)
    s.texel = glm::min(n, glm::ivec2(data_.width - 1, data_.height - 1));
    s.direction = texelToDirection(s.texel.x, s.texel.y, {0.5, 0.5}, data_.width, data_.height);
    return s;
  }
  const glm::vec4& rect = texelRect(n.x, n.y);
  const float tx = std::clamp((ux - rect.x) / rect.z, 0.0f, kOneMinusEpsilonF);
  const float ty = std::clamp((uy - rect.y) / rect.w, 0.0f, kOneMinusEpsilonF);
  const float omega = rowSolidAngles_[std::size_t(n.y)];
  s.texel = n;
  s.direction = texelToDirection(n.x, n.y, {double(tx), double(ty)}, data_.width, data_.height);
  s.pdfSolidAngle = omega > 0.0f ? double(rect.z * rect.w / omega) : 0.0;
  return s;
}

const glm::vec4& EnvHierSampler::texelRect(int x, int y) const {
  return gpu_.texelRects[std::size_t(y) * std::size_t(data_.width) + std::size_t(x)];
}

float EnvHierSampler::texelProbability(int x, int y) const {
  const glm::vec4& rect = texelRect(x, y);
  return rect.z * rect.w;
}

double EnvHierSampler::pdf(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return 0.0;
  const glm::ivec2 t = directionToTexel(wi, data_.width, data_.height);
  const float omega = rowSolidAngles_[std::size_t(t.y)];
  return omega > 0.0f ? double(texelProbability(t.x, t.y) / omega) : 0.0;
}

std::optional<glm::dvec2> EnvHierSampler::invert(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return std::nullopt;
  const glm::ivec2 texel = directionToTexel(wi, data_.width, data_.height);
  const glm::vec4& rect = texelRect(texel.x, texel.y);
  if (!(rect.z > 0.0f && rect.w > 0.0f)) return std::nullopt;
  const glm::dvec2 t = directionToTexelOffset(wi, texel, data_.width, data_.height);
  const glm::dvec2 u(double(rect.x) + t.x * double(rect.z), double(rect.y) + t.y * double(rect.w));
  return glm::min(u, glm::dvec2(double(kOneMinusEpsilonF)));
}

glm::vec4 envHierNodeRect(const EnvHierGpuData& gpu, uint32_t level, uint32_t x, uint32_t y) {
  glm::vec4 rect(0.0f, 0.0f, 1.0f, 1.0f);
  uint32_t g = 0;
  for (uint32_t depth = 1; depth <= level; ++depth) {
    if (g >= gpu.leafStart) throw Error("env-hier: level " + std::to_string(level) + " is below the texels");
    const uint32_t column = (x >> (level - depth)) & 1u, row = (y >> (level - depth)) & 1u;
    rect = childRect(rect, gpu.splits[g], column, row);
    g = hierChild(g, column, row);
  }
  return rect;
}

EnvHierGpuData packEnvHierForGpu(const EnvHierData& data, uint32_t guideSize) {
  if (!hasSquareLevels(data.levels))
    throw Error("env-hier: the pyramid's levels are not 1, 2, 4, ... squared; rebuild it with buildEnvHier");
  EnvHierGpuData gpu;
  const EnvHierLevel& finest = data.levels.back();
  gpu.leafStart = finest.offset;  // levels are stored root first, so the finest level starts after the rest

  // Splits of the interior nodes in heap order (level k's node (x, y) is levels[k].offset + morton(x, y)),
  // from the rectangles, one level at a time from the root: (lo.x, lo.y, hi.x, hi.y) per node, row-major.
  gpu.splits.assign(gpu.leafStart, glm::vec4(0.0f));
  std::vector<glm::vec4> rects{glm::vec4(0.0f, 0.0f, 1.0f, 1.0f)}, finer;
  for (std::size_t k = 0; k + 1 < data.levels.size(); ++k) {
    const uint32_t size = data.levels[k].width;
    const EnvHierLevel& fine = data.levels[k + 1];
    finer.assign(4 * rects.size(), glm::vec4(0.0f));
    for (uint32_t y = 0; y < size; ++y)
      for (uint32_t x = 0; x < size; ++x) {
        const auto q = [&](uint32_t i, uint32_t j) {
          return double(data.nodes[fine.offset + std::size_t(2 * y + j) * fine.width + (2 * x + i)]);
        };
        const glm::vec4 r = rects[std::size_t(y) * size + x];
        const glm::vec4 split(splitPoint(r.x, r.z, firstShare(q(0, 0) + q(0, 1), q(1, 0) + q(1, 1))),
                              splitPoint(r.y, r.w, firstShare(q(0, 0), q(0, 1))),
                              splitPoint(r.y, r.w, firstShare(q(1, 0), q(1, 1))), 0.0f);
        gpu.splits[data.levels[k].offset + mortonIndex(x, y)] = split;
        for (uint32_t column = 0; column < 2; ++column)
          for (uint32_t row = 0; row < 2; ++row)
            finer[std::size_t(2 * y + row) * (2 * size) + (2 * x + column)] =
                childRect(r, split, column, row);
      }
    rects.swap(finer);
  }
  gpu.texelRects.resize(std::size_t(data.width) * std::size_t(data.height));
  for (int y = 0; y < data.height; ++y)
    for (int x = 0; x < data.width; ++x) {
      const glm::vec4 r = rects[std::size_t(y) * finest.width + std::size_t(x)];
      gpu.texelRects[std::size_t(y) * std::size_t(data.width) + std::size_t(x)] =
          glm::vec4(r.x, r.y, r.z - r.x, r.w - r.y);
    }

  // The guide: walk the tree, tracking each node's rectangle, down to the nodes still as large as a guide
  // cell; every cell records the deepest node that contains it (parents are marked first).
  gpu.guideSize = guideSize != 0 ? guideSize : std::min(kEnvHierGuideSize, finest.width);
  if (!std::has_single_bit(gpu.guideSize)) throw Error("env-hier: the guide size must be a power of two");
  const uint32_t cells = gpu.guideSize;
  const double cellsD = double(cells);
  gpu.guideNodes.assign(std::size_t(cells) * cells, 0u);
  struct Pending {
    uint32_t node;
    glm::vec4 rect;  // (lo.x, lo.y, hi.x, hi.y)
  };
  std::vector<Pending> stack{{0u, glm::vec4(0.0f, 0.0f, 1.0f, 1.0f)}};
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    // Cells i with i / G >= lo and (i + 1) / G <= hi: every u of the cell lies in [lo, hi).
    const uint32_t x0 = uint32_t(std::ceil(double(p.rect.x) * cellsD));
    const uint32_t x1 = uint32_t(std::floor(double(p.rect.z) * cellsD));
    const uint32_t y0 = uint32_t(std::ceil(double(p.rect.y) * cellsD));
    const uint32_t y1 = uint32_t(std::floor(double(p.rect.w) * cellsD));
    for (uint32_t cy = y0; cy < y1; ++cy)
      for (uint32_t cx = x0; cx < x1; ++cx) gpu.guideNodes[std::size_t(cy) * cells + cx] = p.node;
    if (p.node >= gpu.leafStart) continue;
    const glm::vec4 split = gpu.splits[p.node];
    for (uint32_t column = 0; column < 2; ++column)
      for (uint32_t row = 0; row < 2; ++row) {
        const glm::vec4 child = childRect(p.rect, split, column, row);
        // A child narrower than a cell holds no whole cell.
        if ((double(child.z) - double(child.x)) * cellsD < 1.0 ||
            (double(child.w) - double(child.y)) * cellsD < 1.0)
          continue;
        stack.push_back({hierChild(p.node, column, row), child});
      }
  }
  return gpu;
}

TechniqueData envHierTechniqueData(const EnvHierSampler& sampler) {
  const EnvHierGpuData& hier = sampler.gpuData();
  TechniqueData data;
  data.add("hierSplits", hier.splits);
  data.add("hierGuide", hier.guideNodes);
  data.add("hierTexelRects", hier.texelRects);
  data.define("ENV_HIER_LEAF_START", hier.leafStart);
  data.define("ENV_HIER_GUIDE_SIZE", hier.guideSize);
  data.define("ENV_HIER_WIDTH", std::to_string(sampler.data().width));
  return data;
}

TechniqueData envHierTechniqueData(const EnvImage& image) {
  return envHierTechniqueData(EnvHierSampler(buildEnvHier(image)));
}

}  // namespace iblx
