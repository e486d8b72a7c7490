// env-hier: mip-pyramid builder (double sums, float storage) and the float-exact CPU twin of the GLSL warp.
#include "engine/sampling/env_hier.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <bit>
#include <limits>
#include <string>
#include <utility>

namespace iblx {
namespace {

// Share of the left column of a 2x2 block; 0.5 when the block is empty (explicit zero guard).
float columnShare(float left, float right) {
  const float total = left + right;
  return total > 0.0f ? left / total : 0.5f;
}

// The GLSL part's hierChoose, operation for operation: takes the first child when u < pFirst, remaps u into
// it; returns 1 for the second. The share taken is never 0 (u in [0, 1) and pFirst in [0, 1]) and the
// remapped u never negative, so only the upper clamp is needed.
uint32_t hierChoose(float pFirst, float& u) {
  const bool second = u >= pFirst;
  const float share = second ? 1.0f - pFirst : pFirst;
  u = std::min((second ? u - pFirst : u) / share, kOneMinusEpsilonF);
  return second ? 1u : 0u;
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

// Interior node (x, y) of level k: its split (pLeft, pTop of the left column, pTop of the right column)
// from its children at level k+1, in the order documented in env_hier.h.
glm::vec3 nodeSplit(const EnvHierData& data, std::size_t k, uint32_t x, uint32_t y) {
  const EnvHierLevel& fine = data.levels[k + 1];
  const auto q = [&](uint32_t i, uint32_t j) {
    return data.nodes[fine.offset + std::size_t(2 * y + j) * fine.width + (2 * x + i)];
  };
  return {columnShare(q(0, 0) + q(0, 1), q(1, 0) + q(1, 1)), columnShare(q(0, 0), q(0, 1)),
          columnShare(q(1, 0), q(1, 1))};
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
  std::size_t offset = 0;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const EnvHierLevel& l = levels[k];
    if (k >= 32 || l.width != (1u << k) || l.height != l.width)
      fail("level sizes are not 1, 2, 4, ... squared");
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
  float ux = toGpuU(u.x), uy = toGpuU(u.y);
  // u * G is exact (G a power of two) and < G for u < 1.
  const uint32_t g = gpu_.guideSize;
  const std::size_t cell =
      std::size_t(std::min(uint32_t(uy * float(g)), g - 1u)) * g + std::min(uint32_t(ux * float(g)), g - 1u);
  const glm::vec4 rect = gpu_.guideRects[cell];
  ux = std::clamp((ux - rect.x) * rect.z, 0.0f, kOneMinusEpsilonF);
  uy = std::clamp((uy - rect.y) * rect.w, 0.0f, kOneMinusEpsilonF);
  uint32_t node = gpu_.guideNodes[cell];
  while (node < gpu_.leafStart) {
    const float* shares = &gpu_.shares[4 * std::size_t(node)];
    const uint32_t column = hierChoose(shares[0], ux);  // column first, then the row inside it
    const uint32_t row = hierChoose(shares[1 + column], uy);
    node = hierChild(node, column, row);
  }
  const uint64_t m = node - gpu_.leafStart;
  const glm::ivec2 n(int(mortonAxis(m)), int(mortonAxis(m >> 1)));
  EnvSample s;
  if (n.x >= data_.width || n.y >= data_.height) {  // padding: unreachable (its shares are 0)
    s.texel = glm::min(n, glm::ivec2(data_.width - 1, data_.height - 1));
    s.direction = texelToDirection(s.texel.x, s.texel.y, {double(ux), double(uy)}, data_.width, data_.height);
    return s;
  }
  const float omega = rowSolidAngles_[std::size_t(n.y)];
  s.texel = n;
  s.direction = texelToDirection(n.x, n.y, {double(ux), double(uy)}, data_.width, data_.height);
  s.pdfSolidAngle = omega > 0.0f ? double(texelProbability(n.x, n.y) / omega) : 0.0;
  return s;
}

float EnvHierSampler::texelProbability(int x, int y) const {
  return gpu_.texelProbability[std::size_t(y) * std::size_t(data_.width) + std::size_t(x)];
}

double EnvHierSampler::pdf(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return 0.0;
  const glm::ivec2 t = directionToTexel(wi, data_.width, data_.height);
  const float omega = rowSolidAngles_[std::size_t(t.y)];
  return omega > 0.0f ? double(texelProbability(t.x, t.y) / omega) : 0.0;
}

std::optional<glm::dvec2> EnvHierSampler::invert(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return std::nullopt;
  const glm::ivec2 target = directionToTexel(wi, data_.width, data_.height);
  // Record the path's splits from the root down, then undo the remaps from the finest level up.
  struct Step {
    float pLeft, pTop;
    uint32_t column, row;
  };
  std::vector<Step> path;
  const int finestLevel = int(data_.levels.size()) - 1;
  for (int k = 0; k < finestLevel; ++k) {
    const uint32_t x = uint32_t(target.x) >> (finestLevel - k), y = uint32_t(target.y) >> (finestLevel - k);
    const glm::vec3 split = nodeSplit(data_, std::size_t(k), x, y);
    const uint32_t column = (uint32_t(target.x) >> (finestLevel - k - 1)) & 1u;
    const uint32_t row = (uint32_t(target.y) >> (finestLevel - k - 1)) & 1u;
    const Step step{split.x, column == 0 ? split.y : split.z, column, row};
    if ((column == 0 ? step.pLeft : 1.0f - step.pLeft) == 0.0f ||
        (row == 0 ? step.pTop : 1.0f - step.pTop) == 0.0f)
      return std::nullopt;
    path.push_back(step);
  }
  glm::dvec2 u = directionToTexelOffset(wi, target, data_.width, data_.height);
  for (auto it = path.rbegin(); it != path.rend(); ++it) {
    // Inverse of hierChoose: u_before = p * u (first) or p + (1 - p) * u (second).
    u.x = it->column == 0 ? double(it->pLeft) * u.x : double(it->pLeft) + double(1.0f - it->pLeft) * u.x;
    u.y = it->row == 0 ? double(it->pTop) * u.y : double(it->pTop) + double(1.0f - it->pTop) * u.y;
  }
  return glm::min(u, glm::dvec2(double(kOneMinusEpsilonF)));
}

EnvHierGpuData packEnvHierForGpu(const EnvHierData& data, uint32_t guideSize) {
  for (std::size_t k = 0; k < data.levels.size(); ++k)
    if (k >= 32 || data.levels[k].width != (1u << k) || data.levels[k].height != (1u << k))
      throw Error(
          "env-hier: the pyramid's levels are not 1, 2, 4, ... squared; rebuild it with buildEnvHier");
  EnvHierGpuData gpu;
  const EnvHierLevel& finest = data.levels.back();
  gpu.leafStart = finest.offset;  // levels are stored root first, so the finest level starts after the rest

  // Interior nodes in heap order: level k's node (x, y) is gpu node levels[k].offset + morton(x, y). Texel
  // probabilities top-down, one level at a time, in the descent's order: column share, then row share.
  gpu.shares.assign(4 * std::size_t(gpu.leafStart), 0.0f);
  std::vector<float> prob{1.0f}, finer;
  for (std::size_t k = 0; k + 1 < data.levels.size(); ++k) {
    const uint32_t size = data.levels[k].width;
    finer.assign(4 * prob.size(), 0.0f);
    for (uint32_t y = 0; y < size; ++y)
      for (uint32_t x = 0; x < size; ++x) {
        const glm::vec3 split = nodeSplit(data, k, x, y);
        float* shares = &gpu.shares[4 * (data.levels[k].offset + mortonIndex(x, y))];
        shares[0] = split.x;
        shares[1] = split.y;
        shares[2] = split.z;
        const float parent = prob[std::size_t(y) * size + x];
        for (uint32_t column = 0; column < 2; ++column) {
          const float shareX = column == 0 ? split.x : 1.0f - split.x;
          const float pTop = column == 0 ? split.y : split.z;
          for (uint32_t row = 0; row < 2; ++row)
            finer[std::size_t(2 * y + row) * (2 * size) + (2 * x + column)] =
                parent * shareX * (row == 0 ? pTop : 1.0f - pTop);
        }
      }
    prob.swap(finer);
  }
  gpu.texelProbability.resize(std::size_t(data.width) * std::size_t(data.height));
  for (int y = 0; y < data.height; ++y)
    std::copy_n(prob.begin() + std::ptrdiff_t(y) * finest.width, data.width,
                gpu.texelProbability.begin() + std::ptrdiff_t(y) * data.width);

  // The guide: walk the tree in double, tracking each node's rectangle in u, down to the nodes still as large
  // as a guide cell; every cell records the deepest node that contains it (parents are marked first).
  gpu.guideSize = guideSize != 0 ? guideSize : std::min(kEnvHierGuideSize, finest.width);
  if (!std::has_single_bit(gpu.guideSize)) throw Error("env-hier: the guide size must be a power of two");
  const uint32_t cells = gpu.guideSize;
  const double cellsD = double(cells);
  gpu.guideRects.assign(std::size_t(cells) * cells, glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));
  gpu.guideNodes.assign(std::size_t(cells) * cells, 0u);
  struct Pending {
    uint32_t node;
    glm::dvec2 lo, hi;  // the node's rectangle in u
  };
  std::vector<Pending> stack{{0u, glm::dvec2(0.0), glm::dvec2(1.0)}};
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    const glm::vec4 rect(float(p.lo.x), float(p.lo.y), float(1.0 / (p.hi.x - p.lo.x)),
                         float(1.0 / (p.hi.y - p.lo.y)));
    // Cells i with i / G >= lo and (i + 1) / G <= hi.
    const uint32_t x0 = uint32_t(std::ceil(p.lo.x * cellsD)), x1 = uint32_t(std::floor(p.hi.x * cellsD));
    const uint32_t y0 = uint32_t(std::ceil(p.lo.y * cellsD)), y1 = uint32_t(std::floor(p.hi.y * cellsD));
    for (uint32_t cy = y0; cy < y1; ++cy)
      for (uint32_t cx = x0; cx < x1; ++cx) {
        gpu.guideRects[std::size_t(cy) * cells + cx] = rect;
        gpu.guideNodes[std::size_t(cy) * cells + cx] = p.node;
      }
    if (p.node >= gpu.leafStart) continue;
    const float* shares = &gpu.shares[4 * std::size_t(p.node)];
    const float pLeft = shares[0];
    for (uint32_t column = 0; column < 2; ++column) {
      const float shareX = column == 0 ? pLeft : 1.0f - pLeft;
      if (!(shareX > 0.0f)) continue;
      const double splitX = p.lo.x + double(pLeft) * (p.hi.x - p.lo.x);
      const double loX = column == 0 ? p.lo.x : splitX, hiX = column == 0 ? splitX : p.hi.x;
      const float pTop = shares[1 + column];
      for (uint32_t row = 0; row < 2; ++row) {
        const float shareY = row == 0 ? pTop : 1.0f - pTop;
        if (!(shareY > 0.0f)) continue;
        const double splitY = p.lo.y + double(pTop) * (p.hi.y - p.lo.y);
        const double loY = row == 0 ? p.lo.y : splitY, hiY = row == 0 ? splitY : p.hi.y;
        if ((hiX - loX) * cellsD < 1.0 || (hiY - loY) * cellsD < 1.0) continue;  // holds no whole cell
        stack.push_back({hierChild(p.node, column, row), {loX, loY}, {hiX, hiY}});
      }
    }
  }
  return gpu;
}

}  // namespace iblx
