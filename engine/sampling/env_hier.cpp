// env-hier: mip-pyramid builder (double sums, float storage) and the float-exact CPU twin of the GLSL warp.
#include "engine/sampling/env_hier.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <bit>
#include <limits>
#include <string>
#include <utility>

namespace iblx {
namespace {

// Share of the left column of a 2x2 (or 2x1) block; 0.5 when the block is empty (explicit zero guard).
float columnShare(float left, float right) {
  const float total = left + right;
  return total > 0.0f ? left / total : 0.5f;
}

// The GLSL part's hierChoose, operation for operation: takes the first child with probability pFirst, remaps
// u and multiplies prob by the share taken; returns 1 for the second.
uint32_t hierChoose(float pFirst, float& u, float& prob) {
  const bool second = u >= pFirst;
  const float share = second ? 1.0f - pFirst : pFirst;
  u = share > 0.0f ? std::clamp((second ? u - pFirst : u) / share, 0.0f, kOneMinusEpsilonF) : 0.0f;
  prob *= share;
  return second ? 1u : 0u;
}

// Morton index of node (x, y) in a level of w x h (powers of two): the low bits of both interleaved with x on
// the even bits, the longer axis' remaining high bits on top.
uint64_t mortonIndex(uint32_t x, uint32_t y, uint32_t w, uint32_t h) {
  const int shortBits = std::countr_zero(std::min(w, h));
  uint64_t m = 0;
  for (int b = 0; b < shortBits; ++b)
    m |= (uint64_t((x >> b) & 1u) << (2 * b)) | (uint64_t((y >> b) & 1u) << (2 * b + 1));
  const uint32_t high = w >= h ? x >> shortBits : y >> shortBits;
  return m | (uint64_t(high) << (2 * shortBits));
}

// Heap index of the child (cx, cy) of node g (EnvHierGpuData): no level table needed.
uint32_t hierChild(const EnvHierGpuData& gpu, uint32_t g, uint32_t cx, uint32_t cy) {
  if (g < gpu.oneAxisNodes) return 2u * g + 1u + cx + cy;
  return uint32_t(int64_t(4u) * g + gpu.quadChildOffset) + cx + 2u * cy;
}

}  // namespace

EnvHierData buildEnvHier(const EnvImage& image) {
  std::vector<double> weights = texelSamplingWeights(image, "env-hier");
  const int width = image.width, height = image.height;
  if (width > (1 << 28) || height > (1 << 28))
    throw Error("env-hier: a " + std::to_string(width) + " x " + std::to_string(height) +
                " map is too large for the pyramid; downsample it");

  // Finest level Pw x Ph: the texel weights, zero padding beyond W x H.
  const int paddedW = int(std::bit_ceil(unsigned(width))), paddedH = int(std::bit_ceil(unsigned(height)));
  glm::ivec2 size(paddedW, paddedH);
  std::vector<double> level;
  if (size == glm::ivec2(width, height)) {
    level = std::move(weights);
  } else {
    level.assign(std::size_t(paddedW) * std::size_t(paddedH), 0.0);
    for (int y = 0; y < height; ++y)
      std::copy_n(weights.begin() + std::ptrdiff_t(image.index(0, y)), width,
                  level.begin() + std::ptrdiff_t(y) * paddedW);
    weights = {};
  }

  // Coarser levels: each node is the sum (in double) of its 2 or 1 children per axis. Only the current level
  // is kept in double; every level is stored as float, finest first while building.
  std::vector<std::vector<float>> stored;
  std::vector<glm::ivec2> sizes;
  const auto store = [&] {
    stored.emplace_back(level.begin(), level.end());
    sizes.push_back(size);
  };
  store();
  while (size.x > 1 || size.y > 1) {
    const glm::ivec2 coarse(std::max(size.x / 2, 1), std::max(size.y / 2, 1));
    const int kx = size.x / coarse.x, ky = size.y / coarse.y;  // children per axis: 2 or 1
    std::vector<double> sums(std::size_t(coarse.x) * std::size_t(coarse.y), 0.0);
    for (int y = 0; y < coarse.y; ++y)
      for (int x = 0; x < coarse.x; ++x) {
        double sum = 0.0;
        for (int j = 0; j < ky; ++j)
          for (int i = 0; i < kx; ++i)
            sum += level[std::size_t(ky * y + j) * std::size_t(size.x) + std::size_t(kx * x + i)];
        sums[std::size_t(y) * std::size_t(coarse.x) + std::size_t(x)] = sum;
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
    data.levels.push_back({uint32_t(offset), uint32_t(sizes[k].x), uint32_t(sizes[k].y), 0u});
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
  if (levels[0].width != 1 || levels[0].height != 1) fail("the root is not 1x1");
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const EnvHierLevel& l = levels[k];
    if (std::size_t(l.offset) + std::size_t(l.width) * l.height > data_.nodes.size())
      fail("nodes out of range");
    if (k == 0) continue;
    const EnvHierLevel& c = levels[k - 1];
    const bool okX = l.width == 2 * c.width || (l.width == 1 && c.width == 1);
    const bool okY = l.height == 2 * c.height || (l.height == 1 && c.height == 1);
    if (!okX || !okY || (l.width == c.width && l.height == c.height)) fail("level sizes do not halve");
  }
  const EnvHierLevel& finest = levels.back();
  if (int(finest.width) < data_.width || int(finest.height) < data_.height) fail("finest level too small");
  for (const EnvHierLevel& l : levels)
    shift_.emplace_back(std::countr_zero(finest.width / l.width), std::countr_zero(finest.height / l.height));
  rowSolidAngles_ = rowSolidAngles(data_.width, data_.height);
  gpu_ = packEnvHierForGpu(data_, guideSize);
}

EnvHierSampler::Children EnvHierSampler::children(int level, glm::ivec2 node) const {
  const EnvHierLevel& cur = data_.levels[std::size_t(level)];
  const EnvHierLevel& fine = data_.levels[std::size_t(level) + 1];
  Children ch;
  ch.splitX = fine.width == 2 * cur.width;
  ch.splitY = fine.height == 2 * cur.height;
  ch.first = {ch.splitX ? 2 * node.x : node.x, ch.splitY ? 2 * node.y : node.y};
  for (int i = 0; i < (ch.splitX ? 2 : 1); ++i)
    for (int j = 0; j < (ch.splitY ? 2 : 1); ++j)
      ch.q[i][j] =
          data_.nodes[fine.offset + std::size_t(ch.first.y + j) * fine.width + std::size_t(ch.first.x + i)];
  return ch;
}

EnvSample EnvHierSampler::sample(glm::dvec2 u) const {
  float ux = toGpuU(u.x), uy = toGpuU(u.y);
  // u * G is exact (G a power of two) and < G for u < 1.
  const uint32_t g = gpu_.guideSize;
  const EnvHierStart& start = gpu_.guide[std::size_t(std::min(uint32_t(uy * float(g)), g - 1u)) * g +
                                         std::min(uint32_t(ux * float(g)), g - 1u)];
  ux = std::clamp((ux - start.minX) * start.invSizeX, 0.0f, kOneMinusEpsilonF);
  uy = std::clamp((uy - start.minY) * start.invSizeY, 0.0f, kOneMinusEpsilonF);
  float prob = start.prob;
  uint32_t node = start.node;
  glm::ivec2 n(int(start.x), int(start.y));
  while (node < gpu_.leafStart) {
    const float* shares = &gpu_.shares[4 * std::size_t(node)];
    // Column first, then the row inside the chosen column. Along an axis that does not split the share is 1,
    // which leaves u unchanged.
    const uint32_t column = hierChoose(shares[0], ux, prob);
    const uint32_t row = hierChoose(shares[1 + column], uy, prob);
    n = 2 * n + glm::ivec2(int(column), int(row));  // a 1-wide axis stays 0
    node = hierChild(gpu_, node, column, row);
  }
  EnvSample s;
  if (n.x >= data_.width || n.y >= data_.height) {  // padding: unreachable unless every share underflowed
    s.texel = glm::min(n, glm::ivec2(data_.width - 1, data_.height - 1));
    s.direction = texelToDirection(s.texel.x, s.texel.y, {double(ux), double(uy)}, data_.width, data_.height);
    return s;
  }
  const float omega = rowSolidAngles_[std::size_t(n.y)];
  s.texel = n;
  s.direction = texelToDirection(n.x, n.y, {double(ux), double(uy)}, data_.width, data_.height);
  s.pdfSolidAngle = omega > 0.0f ? double(prob / omega) : 0.0;
  return s;
}

float EnvHierSampler::texelProbability(int x, int y) const {
  const glm::ivec2 target(x, y);
  float prob = 1.0f;
  glm::ivec2 n(0);
  for (int k = 0; k + 1 < int(data_.levels.size()); ++k) {
    const Children ch = children(k, n);
    const glm::ivec2 next(target.x >> shift_[std::size_t(k) + 1].x, target.y >> shift_[std::size_t(k) + 1].y);
    const int column = next.x - ch.first.x, row = next.y - ch.first.y;
    if (ch.splitX) {
      const float pLeft = columnShare(ch.q[0][0] + ch.q[0][1], ch.q[1][0] + ch.q[1][1]);
      prob *= column == 0 ? pLeft : 1.0f - pLeft;
    }
    if (ch.splitY) {
      const float pTop = columnShare(ch.q[column][0], ch.q[column][1]);
      prob *= row == 0 ? pTop : 1.0f - pTop;
    }
    n = next;
  }
  return prob;
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
  // Record the path's shares from the root down, then undo the remaps from the finest level up.
  struct Split {
    bool splitX, splitY;
    float pLeft, pTop;
    int column, row;
  };
  std::vector<Split> path;
  glm::ivec2 n(0);
  for (int k = 0; k + 1 < int(data_.levels.size()); ++k) {
    const Children ch = children(k, n);
    const glm::ivec2 next(target.x >> shift_[std::size_t(k) + 1].x, target.y >> shift_[std::size_t(k) + 1].y);
    Split s{ch.splitX, ch.splitY, 1.0f, 1.0f, next.x - ch.first.x, next.y - ch.first.y};
    if (s.splitX) s.pLeft = columnShare(ch.q[0][0] + ch.q[0][1], ch.q[1][0] + ch.q[1][1]);
    if (s.splitY) s.pTop = columnShare(ch.q[s.column][0], ch.q[s.column][1]);
    if ((s.splitX && (s.column == 0 ? s.pLeft : 1.0f - s.pLeft) == 0.0f) ||
        (s.splitY && (s.row == 0 ? s.pTop : 1.0f - s.pTop) == 0.0f))
      return std::nullopt;
    path.push_back(s);
    n = next;
  }
  glm::dvec2 u = directionToTexelOffset(wi, target, data_.width, data_.height);
  for (auto it = path.rbegin(); it != path.rend(); ++it) {
    // Inverse of chooseBranch: u_before = p * u (first) or p + (1 - p) * u (second).
    if (it->splitX)
      u.x = it->column == 0 ? double(it->pLeft) * u.x : double(it->pLeft) + double(1.0f - it->pLeft) * u.x;
    if (it->splitY)
      u.y = it->row == 0 ? double(it->pTop) * u.y : double(it->pTop) + double(1.0f - it->pTop) * u.y;
  }
  return glm::min(u, glm::dvec2(double(kOneMinusEpsilonF)));
}

EnvHierGpuData packEnvHierForGpu(const EnvHierData& data, uint32_t guideSize) {
  EnvHierGpuData gpu;
  const EnvHierLevel& finest = data.levels.back();
  const int bitsX = std::countr_zero(finest.width), bitsY = std::countr_zero(finest.height);
  const int oneAxisLevels = std::abs(bitsX - bitsY);
  gpu.levelCount = uint32_t(data.levels.size());
  gpu.finestWidth = finest.width;
  gpu.finestHeight = finest.height;
  gpu.oneAxisNodes = (1u << oneAxisLevels) - 1u;
  gpu.quadChildOffset = 3 - (int32_t(1) << (oneAxisLevels + 1));
  gpu.leafStart = finest.offset;  // levels are stored root first, so the finest level starts after the rest

  // Interior nodes in heap order: level k's node (x, y) is gpu node levels[k].offset + morton(x, y).
  gpu.shares.assign(4 * std::size_t(gpu.leafStart), 0.0f);
  for (std::size_t k = 0; k + 1 < data.levels.size(); ++k) {
    const EnvHierLevel& coarse = data.levels[k];
    const EnvHierLevel& fine = data.levels[k + 1];
    const bool splitX = fine.width > coarse.width, splitY = fine.height > coarse.height;
    for (uint32_t y = 0; y < coarse.height; ++y)
      for (uint32_t x = 0; x < coarse.width; ++x) {
        const uint32_t x0 = splitX ? 2 * x : x, y0 = splitY ? 2 * y : y;
        auto node = [&](uint32_t cx, uint32_t cy) { return data.nodes[fine.offset + cy * fine.width + cx]; };
        const float q00 = node(x0, y0), q10 = splitX ? node(x0 + 1, y0) : 0.0f;
        const float q01 = splitY ? node(x0, y0 + 1) : 0.0f,
                    q11 = splitX && splitY ? node(x0 + 1, y0 + 1) : 0.0f;
        // The same float operations as texelProbability, so sample() and pdf() multiply identical shares.
        float* shares = &gpu.shares[4 * (coarse.offset + mortonIndex(x, y, coarse.width, coarse.height))];
        shares[0] = splitX ? columnShare(q00 + q01, q10 + q11) : 1.0f;
        shares[1] = splitY ? columnShare(q00, q01) : 1.0f;
        shares[2] = splitY ? columnShare(q10, q11) : 1.0f;
      }
  }

  // The guide: walk the tree in double, tracking each node's rectangle in u, down to the nodes still as large
  // as a guide cell; every cell records the deepest node that contains it (parents are marked first).
  gpu.guideSize =
      guideSize != 0 ? guideSize : std::min<uint32_t>(256u, std::max(finest.width, finest.height));
  if (!std::has_single_bit(gpu.guideSize)) throw Error("env-hier: the guide size must be a power of two");
  const uint32_t cells = gpu.guideSize;
  const double cellsD = double(cells);
  gpu.guide.assign(std::size_t(cells) * cells, EnvHierStart{});
  struct Pending {
    EnvHierStart start;
    glm::dvec2 lo, hi;  // the node's rectangle in u
  };
  std::vector<Pending> stack{{EnvHierStart{}, glm::dvec2(0.0), glm::dvec2(1.0)}};
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    EnvHierStart start = p.start;
    start.minX = float(p.lo.x);
    start.minY = float(p.lo.y);
    start.invSizeX = float(1.0 / (p.hi.x - p.lo.x));
    start.invSizeY = float(1.0 / (p.hi.y - p.lo.y));
    // Cells i with i / G >= lo and (i + 1) / G <= hi.
    const uint32_t x0 = uint32_t(std::ceil(p.lo.x * cellsD)), x1 = uint32_t(std::floor(p.hi.x * cellsD));
    const uint32_t y0 = uint32_t(std::ceil(p.lo.y * cellsD)), y1 = uint32_t(std::floor(p.hi.y * cellsD));
    for (uint32_t cy = y0; cy < y1; ++cy)
      for (uint32_t cx = x0; cx < x1; ++cx) gpu.guide[std::size_t(cy) * cells + cx] = start;
    if (p.start.node >= gpu.leafStart) continue;
    const float* shares = &gpu.shares[4 * std::size_t(p.start.node)];
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
        Pending child{p.start, {loX, loY}, {hiX, hiY}};
        child.start.prob = p.start.prob * shareX * shareY;  // the GPU's order: prob *= shareX; prob *= shareY
        child.start.node = hierChild(gpu, p.start.node, column, row);
        child.start.x = 2 * p.start.x + column;
        child.start.y = 2 * p.start.y + row;
        stack.push_back(child);
      }
    }
  }
  return gpu;
}

}  // namespace iblx
