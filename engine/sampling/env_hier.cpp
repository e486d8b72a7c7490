// env-hier: mip-pyramid builder (double sums, float storage) and the float-exact CPU twin of the GLSL warp.
#include "engine/sampling/env_hier.h"

#include "engine/core/error.h"

#include <algorithm>
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

// One binary choice of the warp: u < p goes first (u /= p), else second (u = (u - p) / (1 - p)); returns the
// chosen share and the branch, u stays in [0, 1 - 2^-24].
float chooseBranch(float p, float& u, int& branch) {
  float share;
  if (u < p) {
    branch = 0;
    share = p;
    u = u / p;
  } else {
    branch = 1;
    share = 1.0f - p;
    u = (u - p) / share;  // share > 0: with p = 1 every u < 1 takes the first branch
  }
  u = std::clamp(u, 0.0f, kOneMinusEpsilonF);
  return share;
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

EnvHierSampler::EnvHierSampler(EnvHierData data) : data_(std::move(data)) {
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
  float prob = 1.0f;
  glm::ivec2 n(0);
  for (int k = 0; k + 1 < int(data_.levels.size()); ++k) {
    const Children ch = children(k, n);
    int column = 0, row = 0;
    // Column first: split the block by the local ratio of its left column.
    if (ch.splitX)
      prob *= chooseBranch(columnShare(ch.q[0][0] + ch.q[0][1], ch.q[1][0] + ch.q[1][1]), ux, column);
    // Then the row inside the chosen column.
    if (ch.splitY) prob *= chooseBranch(columnShare(ch.q[column][0], ch.q[column][1]), uy, row);
    n = ch.first + glm::ivec2(column, row);
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

EnvHierGpuData packEnvHierForGpu(const EnvHierData& data) {
  EnvHierGpuData gpu;
  const std::size_t levelCount = data.levels.size();
  auto log2 = [](uint32_t v) {
    uint32_t l = 0;
    while (v > 1) v >>= 1, ++l;
    return l;
  };
  const EnvHierLevel& finest = data.levels.back();
  for (std::size_t k = 0; k + 1 < levelCount; ++k) {
    const EnvHierLevel& coarse = data.levels[k];
    const EnvHierLevel& fine = data.levels[k + 1];
    const bool splitX = fine.width > coarse.width, splitY = fine.height > coarse.height;
    const uint32_t shiftX = log2(finest.width) - log2(fine.width) + (splitX ? 1 : 0);
    const uint32_t shiftY = log2(finest.height) - log2(fine.height) + (splitY ? 1 : 0);
    EnvHierLevel info{uint32_t(gpu.children.size() / 4), coarse.width, coarse.height,
                      (splitX ? 1u : 0u) | (splitY ? 2u : 0u) | (shiftX << 8) | (shiftY << 16)};
    gpu.levels.push_back(info);
    for (uint32_t y = 0; y < coarse.height; ++y)
      for (uint32_t x = 0; x < coarse.width; ++x) {
        const uint32_t x0 = splitX ? 2 * x : x, y0 = splitY ? 2 * y : y;
        auto node = [&](uint32_t cx, uint32_t cy) { return data.nodes[fine.offset + cy * fine.width + cx]; };
        gpu.children.push_back(node(x0, y0));
        gpu.children.push_back(splitX ? node(x0 + 1, y0) : 0.0f);
        gpu.children.push_back(splitY ? node(x0, y0 + 1) : 0.0f);
        gpu.children.push_back(splitX && splitY ? node(x0 + 1, y0 + 1) : 0.0f);
      }
  }
  return gpu;
}

}  // namespace iblx
