// env-hier product level: the level's node rectangles and centres, and the CPU twin of the product sampler.
#include "engine/sampling/product/env_hier_product.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace iblx {
namespace {

// Node columns and rows that hold texels at pyramid level k, of a map whose pyramid is `size` texels across.
std::pair<uint32_t, uint32_t> levelExtent(const EnvHierData& data, uint32_t k) {
  const uint32_t size = data.levels.back().width, width = 1u << k, per = size >> k;
  return {width, (uint32_t(data.height) + per - 1) / per};
}

// The finest level whose nodes number at most maxNodes.
uint32_t productLevelIndex(const EnvHierData& data, uint32_t maxNodes) {
  if (maxNodes == 0) throw Error("env-hier product level: at least one node is needed");
  uint32_t level = 0;
  for (uint32_t k = 0; k < data.levels.size(); ++k) {
    const auto [width, rows] = levelExtent(data, k);
    if (uint64_t(width) * rows <= maxNodes) level = k;
  }
  return level;
}

EnvProductLevel productLevelAt(const EnvHierSampler& env, uint32_t level) {
  const EnvHierData& data = env.data();
  EnvProductLevel l;
  std::tie(l.width, l.rows) = levelExtent(data, level);
  l.texelsPerNode = data.levels.back().width >> level;
  for (uint32_t y = 0; y < l.rows; ++y)
    for (uint32_t x = 0; x < l.width; ++x) {
      l.rects.push_back(envHierNodeRect(env.gpuData(), level, x, y));
      // The centre of the node's texels (the part of its block inside the map): u, v of docs/DESIGN.md §3.
      const double x0 = double(x * l.texelsPerNode), y0 = double(y * l.texelsPerNode);
      const double x1 = std::min(x0 + l.texelsPerNode, double(data.width)),
                   y1 = std::min(y0 + l.texelsPerNode, double(data.height));
      const glm::dvec3 d =
          x0 < x1 ? latLongToDirection({0.5 * (x0 + x1) / data.width, 0.5 * (y0 + y1) / data.height})
                  : glm::dvec3(0.0, 1.0, 0.0);
      // The angular radius from a 17 x 17 grid over the block (its edges included), widened by one grid
      // step's angle so that no point of the block lies outside the cap.
      double cosRadius = 1.0;
      constexpr int kGrid = 16;
      for (int b = 0; b <= kGrid && x0 < x1; ++b)
        for (int a = 0; a <= kGrid; ++a) {
          const glm::dvec2 uv((x0 + (x1 - x0) * a / kGrid) / data.width,
                              (y0 + (y1 - y0) * b / kGrid) / data.height);
          cosRadius = std::min(cosRadius, glm::dot(d, latLongToDirection(uv)));
        }
      const double step = std::max(2.0 * kPi * (x1 - x0) / data.width, kPi * (y1 - y0) / data.height) / kGrid;
      const double radius = std::min(std::acos(std::clamp(cosRadius, -1.0, 1.0)) + step, kPi);
      l.centers.emplace_back(glm::vec3(d), float(std::cos(radius)));
    }
  return l;
}

}  // namespace

EnvProductLevel buildEnvProductLevel(const EnvHierSampler& env, uint32_t maxNodes) {
  return productLevelAt(env, productLevelIndex(env.data(), maxNodes));
}

std::vector<EnvProductLevel> buildEnvProductLevels(const EnvHierSampler& env, uint32_t maxNodes,
                                                   uint32_t maxDepth) {
  const uint32_t level = productLevelIndex(env.data(), maxNodes),
                 finest = uint32_t(env.data().levels.size() - 1);
  std::vector<EnvProductLevel> levels;
  for (uint32_t k = level; k <= std::min(finest, level + maxDepth); ++k)
    levels.push_back(productLevelAt(env, k));
  return levels;
}

EnvProductLevel buildEnvProductGrid(const EnvHierSampler& env, uint32_t width, uint32_t rows) {
  if (width == 0 || rows == 0) throw Error("env-hier product grid: at least one cell is needed");
  // A texel's angular size: the margin of every cap (a cell's image holds whole texels' pieces).
  const double texel = std::max(2.0 * kPi / env.data().width, kPi / env.data().height);
  return buildEnvProductGrid([&env](glm::dvec2 u) { return env.sample(u).direction; }, texel, width, rows);
}

EnvProductLevel buildEnvProductGrid(const std::function<glm::dvec3(glm::dvec2)>& tail, double texelAngle,
                                    uint32_t width, uint32_t rows) {
  if (width == 0 || rows == 0) throw Error("env product grid: at least one cell is needed");
  EnvProductLevel l;
  l.width = width;
  l.rows = rows;
  l.uniformGrid = true;
  for (uint32_t y = 0; y < rows; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const glm::vec4 rect(float(x) / float(width), float(y) / float(rows), float(x + 1) / float(width),
                           float(y + 1) / float(rows));
      l.rects.push_back(rect);
      // The cell's image under the tail, from a 17 x 17 grid of u inside it: the mean direction and the
      // largest angle from it.
      constexpr int kGrid = 16;
      std::vector<glm::dvec3> image;
      glm::dvec3 sum(0.0);
      for (int b = 0; b <= kGrid; ++b)
        for (int a = 0; a <= kGrid; ++a) {
          const glm::dvec2 u(double(rect.x) + (rect.z - rect.x) * (a + 0.5) / (kGrid + 1),
                             double(rect.y) + (rect.w - rect.y) * (b + 0.5) / (kGrid + 1));
          image.push_back(tail(u));
          sum += image.back();
        }
      const double length = glm::length(sum);
      const glm::dvec3 centre = length > 1e-9 ? sum / length : image.front();
      double cosRadius = 1.0;
      for (const glm::dvec3& w : image) cosRadius = std::min(cosRadius, glm::dot(centre, w));
      const double radius = std::min(std::acos(std::clamp(cosRadius, -1.0, 1.0)) + texelAngle, kPi);
      l.centers.emplace_back(glm::vec3(centre), float(std::cos(radius)));
    }
  return l;
}

glm::dvec3 closestDirectionInCap(glm::dvec3 centre, double cosRadius, glm::dvec3 towards) {
  const double cosAngle = glm::dot(centre, towards);
  if (cosAngle >= cosRadius) return towards;
  const glm::dvec3 tangent = towards - centre * cosAngle;
  const double length = glm::length(tangent);
  if (!(length > 1e-12)) return centre;  // towards is opposite the centre: every direction is as close
  const double sinRadius = std::sqrt(std::max(0.0, 1.0 - cosRadius * cosRadius));
  return centre * cosRadius + tangent * (sinRadius / length);
}

std::vector<double> envProductWeights(const EnvProductLevel& level, std::span<const double> fCos) {
  const std::size_t n = level.nodes();
  if (fCos.size() != n) throw Error("env product sampler: one f cos value per node is needed");
  std::vector<double> area(n), weight(n);
  double sumEF = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const glm::vec4& r = level.rects[j];
    area[j] = double((r.z - r.x) * (r.w - r.y));
    sumEF += area[j] * std::max(fCos[j], 0.0);
  }
  for (std::size_t j = 0; j < n; ++j)
    weight[j] =
        sumEF > 0.0
            ? area[j] * ((1.0 - kEnvProductDefensive) * std::max(fCos[j], 0.0) / sumEF + kEnvProductDefensive)
            : area[j];
  return weight;
}

std::vector<uint32_t> quantizedRunningSums(std::span<const double> weights) {
  double total = 0.0;
  uint32_t positive = 0;
  for (double w : weights) {
    if (!(w >= 0.0) || !std::isfinite(w))
      throw Error("product table: the weights must be finite and >= 0, got " + std::to_string(w));
    total += w;
    positive += w > 0.0 ? 1 : 0;
  }
  if (positive > kProductFullScale)
    throw Error("product table: more than " + std::to_string(kProductFullScale) + " positive weights");
  std::vector<uint32_t> sums(weights.size(), 0);
  if (!(total > 0.0)) return sums;
  const double steps = double(kProductFullScale - positive);
  double running = 0.0;
  uint32_t counted = 0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    running += weights[i];
    counted += weights[i] > 0.0 ? 1 : 0;
    sums[i] = uint32_t(std::min(std::round(running / total * steps), steps)) + counted;
  }
  sums.back() = kProductFullScale;  // the running sum's rounding cannot leave the last below the scale
  return sums;
}

std::vector<double> quantizedNodeProbabilities(const EnvProductLevel& level,
                                               std::span<const double> weights) {
  if (weights.size() != level.nodes()) throw Error("product table: one weight per node is needed");
  std::vector<double> rowTotals(level.rows, 0.0), probability(weights.size(), 0.0);
  for (std::size_t j = 0; j < weights.size(); ++j) rowTotals[j / level.width] += weights[j];
  const std::vector<uint32_t> rows = quantizedRunningSums(rowTotals);
  const double scale = double(kProductFullScale);
  for (uint32_t y = 0; y < level.rows; ++y) {
    const uint32_t rowStep = rows[y] - (y == 0 ? 0 : rows[y - 1]);
    const std::vector<uint32_t> columns = quantizedRunningSums(weights.subspan(y * level.width, level.width));
    for (uint32_t x = 0; x < level.width; ++x)
      probability[y * level.width + x] =
          double(rowStep) / scale * double(columns[x] - (x == 0 ? 0 : columns[x - 1])) / scale;
  }
  return probability;
}

namespace {

double rectArea(const glm::vec4& r) {
  return double((r.z - r.x) * (r.w - r.y));  // in float, as the GPU computes it
}

// The child c = a + 2 b of node `node` of levels[depth] in levels[depth + 1]: (2x + a, 2y + b); npos when
// that row lies past the map.
std::size_t childOf(std::span<const EnvProductLevel> levels, uint32_t depth, std::size_t node, uint32_t c) {
  const EnvProductLevel &level = levels[depth], &finer = levels[depth + 1];
  const std::size_t x = 2 * (node % level.width) + (c & 1), y = 2 * (node / level.width) + (c >> 1);
  return y < finer.rows ? y * finer.width + x : std::size_t(-1);
}

// The indices of the `count` largest positive values, largest first, the lower index first among equal
// ones: the GPU's insertion into a sorted list (PRODUCT_KEEP_LARGEST).
std::vector<std::size_t> largestPositive(std::span<const double> values, std::size_t count) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (values[i] > 0.0) order.push_back(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return values[a] > values[b]; });
  if (order.size() > count) order.resize(count);
  return order;
}

// A split node's children's 16-bit running sums from their E_c and e_c = E_c F_c:
// w_c = (1 - d) e_c / sum e + d E_c / sum E (E_c / sum E when no child has a lobe value).
std::vector<uint32_t> childSums(std::span<const double> areas, std::span<const double> products) {
  double sumArea = 0.0, sumProduct = 0.0;
  for (std::size_t c = 0; c < areas.size(); ++c) sumArea += areas[c], sumProduct += products[c];
  std::vector<double> weights(areas.size(), 0.0);
  for (std::size_t c = 0; c < areas.size() && sumArea > 0.0; ++c)
    weights[c] = sumProduct > 0.0 ? (1.0 - kEnvProductDefensive) * products[c] / sumProduct +
                                        kEnvProductDefensive * areas[c] / sumArea
                                  : areas[c] / sumArea;
  return quantizedRunningSums(weights);
}

// The point of `rect` where v in [0,1]^2 puts u: a float set, one float step below its upper edges at most.
glm::dvec2 pointInRect(glm::dvec2 v, const glm::vec4& r) {
  return {std::clamp(double(r.x) + v.x * double(r.z - r.x), double(r.x), double(std::nextafter(r.z, r.x))),
          std::clamp(double(r.y) + v.y * double(r.w - r.y), double(r.y), double(std::nextafter(r.w, r.y)))};
}

// The child whose quantized interval [start, end) holds t in [0, 65535): the first whose running sum exceeds
// t, as the GPU counts them.
uint32_t childChoice(const std::vector<uint32_t>& sums, double t, double& start, double& end) {
  uint32_t c = 0;
  while (c + 1 < sums.size() && double(sums[c]) <= t) ++c;
  start = c == 0 ? 0.0 : double(sums[c - 1]);
  end = double(sums[c]);
  return c;
}

}  // namespace

EnvProductSampler::EnvProductSampler(const EnvHierSampler& env, const EnvProductLevel& level,
                                     std::span<const double> fCos)
    : EnvProductSampler(env, std::span(&level, 1),
                        Tables{quantizedNodeProbabilities(level, envProductWeights(level, fCos)),
                               std::vector<int>(level.nodes(), -1),
                               {},
                               {},
                               {}}) {}

EnvProductSampler::EnvProductSampler(const EnvHierSampler& env, std::span<const EnvProductLevel> levels,
                                     const ProductCapLobe& lobe)
    : EnvProductSampler(env, levels, refinedTables(levels, lobe)) {}

EnvProductSampler::EnvProductSampler(const EnvHierSampler& env, std::span<const EnvProductLevel> levels,
                                     Tables tables)
    : env_(env),
      levels_(levels),
      tables_(std::move(tables)),
      nodes_(tables_.probability, int(levels.front().width), int(levels.front().rows)) {}

EnvProductSampler::Tables EnvProductSampler::refinedTables(std::span<const EnvProductLevel> levels,
                                                           const ProductCapLobe& lobe) {
  if (levels.empty() || levels.front().uniformGrid)
    throw Error("env product sampler: the refinement needs a pyramid level");
  // E F of a node at depth k (0 for an absent one): F clamped to finite values >= 0, as the GPU does.
  const auto product = [&](uint32_t depth, std::size_t node) {
    if (node == std::size_t(-1)) return 0.0;
    const double area = rectArea(levels[depth].rects[node]);
    if (!(area > 0.0)) return 0.0;
    const double f = lobe(levels[depth].centers[node]);
    return std::isfinite(f) && f > 0.0 ? area * f : 0.0;
  };
  const auto area = [&](uint32_t depth, std::size_t node) {
    return node == std::size_t(-1) ? 0.0 : rectArea(levels[depth].rects[node]);
  };
  const EnvProductLevel& top = levels.front();
  Tables t;
  t.recordOfNode.assign(top.nodes(), -1);
  std::vector<double> products(top.nodes());
  for (std::size_t j = 0; j < top.nodes(); ++j) products[j] = product(0, j);
  if (levels.size() > 1) {
    const std::vector<std::size_t> split = largestPositive(products, kProductRefinedNodes);
    // Per split node s, its children at 4 s + c.
    std::vector<double> childProducts(4 * split.size(), 0.0), childAreas(4 * split.size(), 0.0);
    for (std::size_t s = 0; s < split.size(); ++s)
      for (uint32_t c = 0; c < 4; ++c) {
        const std::size_t child = childOf(levels, 0, split[s], c);
        childProducts[4 * s + c] = product(1, child);
        childAreas[4 * s + c] = area(1, child);
      }
    t.records.resize(split.size());
    if (levels.size() > 2) {
      std::vector<std::size_t> again = largestPositive(childProducts, kProductRefinedChildren);
      std::sort(again.begin(), again.end());  // records by parent, then child
      for (const std::size_t k : again) {
        const std::size_t child = childOf(levels, 0, split[k / 4], uint32_t(k % 4));
        double grandProducts[4], grandAreas[4], sum = 0.0;
        for (uint32_t g = 0; g < 4; ++g) {
          const std::size_t grand = childOf(levels, 1, child, g);
          grandProducts[g] = product(2, grand);
          grandAreas[g] = area(2, grand);
          sum += grandProducts[g];
        }
        childProducts[k] = sum;  // revalued by the finer look
        t.records[k / 4].childRecord[k % 4] = int(t.records.size());
        t.records.push_back({childSums(grandAreas, grandProducts), {-1, -1, -1, -1}});
        t.refinedChildren.push_back(child);
      }
    }
    for (std::size_t s = 0; s < split.size(); ++s) {
      const std::span<const double> p(childProducts.data() + 4 * s, 4), a(childAreas.data() + 4 * s, 4);
      products[split[s]] = p[0] + p[1] + p[2] + p[3];
      t.records[s].sums = childSums(a, p);
      t.recordOfNode[split[s]] = int(s);
    }
    t.refinedNodes = split;
  }
  // The table's weights by envProductWeights' rule, from each node's (revalued) F = E F / E.
  std::vector<double> fCos(top.nodes(), 0.0);
  for (std::size_t j = 0; j < top.nodes(); ++j)
    if (const double e = area(0, j); e > 0.0) fCos[j] = products[j] / e;
  t.probability = quantizedNodeProbabilities(top, envProductWeights(top, fCos));
  return t;
}

std::size_t EnvProductSampler::nodeOf(glm::dvec3 wi) const {
  const EnvProductLevel& level = levels_.front();
  if (level.uniformGrid) {
    const glm::dvec2 u = env_.invert(wi).value_or(glm::dvec2(0.0));
    return std::min(std::size_t(u.y * level.rows), std::size_t(level.rows - 1)) * level.width +
           std::min(std::size_t(u.x * level.width), std::size_t(level.width - 1));
  }
  const glm::ivec2 texel = directionToTexel(wi, env_.data().width, env_.data().height);
  return std::size_t(uint32_t(texel.y) / level.texelsPerNode) * level.width +
         uint32_t(texel.x) / level.texelsPerNode;
}

ProductLeaf EnvProductSampler::leafOf(glm::dvec3 wi) const {
  ProductLeaf leaf{0, nodeOf(wi), 0.0};
  leaf.probability = tables_.probability[leaf.node];
  const glm::ivec2 texel = directionToTexel(wi, env_.data().width, env_.data().height);
  for (int record = tables_.recordOfNode[leaf.node]; record >= 0;) {
    const Record& r = tables_.records[std::size_t(record)];
    const uint32_t per = levels_[leaf.depth + 1].texelsPerNode;
    const uint32_t c = ((uint32_t(texel.x) / per) & 1) + 2 * ((uint32_t(texel.y) / per) & 1);
    leaf.probability *= double(r.sums[c] - (c == 0 ? 0 : r.sums[c - 1])) / kProductFullScale;
    leaf.node = childOf(levels_, leaf.depth, leaf.node, c);
    ++leaf.depth;
    record = r.childRecord[c];
  }
  return leaf;
}

glm::dvec2 pointInProductNode(const PiecewiseConstant2D::Sample& chosen, const EnvProductLevel& level,
                              std::size_t j) {
  const glm::dvec2 v = glm::clamp(chosen.p * glm::dvec2(level.width, level.rows) - glm::dvec2(chosen.bin),
                                  glm::dvec2(0.0), glm::dvec2(1.0));
  return pointInRect(v, level.rects[j]);
}

EnvSample EnvProductSampler::sample(glm::dvec2 u) const {
  const EnvProductLevel& top = levels_.front();
  const PiecewiseConstant2D::Sample chosen = nodes_.sample(u);
  ProductLeaf leaf{0, std::size_t(chosen.bin.y) * top.width + std::size_t(chosen.bin.x), 0.0};
  leaf.probability = tables_.probability[leaf.node];
  if (!(leaf.probability > 0.0)) return {};  // an all-zero table: no node to choose
  glm::dvec2 v = glm::clamp(chosen.p * glm::dvec2(top.width, top.rows) - glm::dvec2(chosen.bin),
                            glm::dvec2(0.0), glm::dvec2(1.0));
  // The records below the node: the first split reads u.x, the second u.y, each rescaled inside the child.
  for (int record = tables_.recordOfNode[leaf.node]; record >= 0;) {
    const Record& r = tables_.records[std::size_t(record)];
    double& coordinate = leaf.depth == 0 ? v.x : v.y;
    double start, end;
    const uint32_t c = childChoice(r.sums, coordinate * kProductFullScale, start, end);
    if (!(end > start)) return {};
    leaf.probability *= (end - start) / kProductFullScale;
    coordinate = std::clamp((coordinate * kProductFullScale - start) / (end - start), 0.0, 1.0);
    leaf.node = childOf(levels_, leaf.depth, leaf.node, c);
    ++leaf.depth;
    record = r.childRecord[c];
  }
  const glm::vec4& rect = levels_[leaf.depth].rects[leaf.node];
  // The chosen node's probability over its area, times env-hier's density inside it.
  EnvSample s = env_.sample(pointInRect(v, rect));
  const double area = rectArea(rect);
  s.pdfSolidAngle = area > 0.0 ? leaf.probability / area * s.pdfSolidAngle : 0.0;
  return s;
}

double EnvProductSampler::pdf(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return 0.0;
  const ProductLeaf leaf = leafOf(wi);
  const double area = rectArea(levels_[leaf.depth].rects[leaf.node]);
  return area > 0.0 ? leaf.probability / area * env_.pdf(wi) : 0.0;
}

TechniqueData envHierProductTechniqueData(const EnvImage& image) {
  const EnvHierSampler sampler(buildEnvHier(image));
  TechniqueData data = envHierTechniqueData(sampler);
  const std::vector<EnvProductLevel> levels = buildEnvProductLevels(sampler);
  const EnvProductLevel& product = levels.front();
  const EnvProductLevel grid = buildEnvProductGrid(sampler);
  if (productTableWords(product.width, product.rows) + productRefineWords(uint32_t(product.nodes())) >
      kEnvProductMaxTableWords)
    throw Error("env-hier product: a " + std::to_string(product.width) + "x" + std::to_string(product.rows) +
                " node table does not fit a pixel's stored table of " +
                std::to_string(kEnvProductMaxTableWords) + " words");
  // The level's nodes, then the finer levels ordered by parent: index 4 p + c at depth k + 1 for child c of
  // index p at depth k (the node's own index at depth 0), an absent child an empty rectangle.
  std::vector<glm::vec4> rects = product.rects, centers = product.centers;
  std::vector<std::size_t> parents(product.nodes());
  for (std::size_t j = 0; j < parents.size(); ++j) parents[j] = j;
  for (uint32_t depth = 1; depth < levels.size(); ++depth) {
    std::vector<std::size_t> children;
    const EnvProductLevel& finer = levels[depth];
    for (const std::size_t p : parents)
      for (uint32_t c = 0; c < 4; ++c) {
        children.push_back(p == std::size_t(-1) ? p : childOf(levels, depth - 1, p, c));
        const bool present = children.back() != std::size_t(-1);
        rects.push_back(present ? finer.rects[children.back()] : glm::vec4(0.0f));
        centers.push_back(present ? finer.centers[children.back()] : glm::vec4(0.0f, 1.0f, 0.0f, -1.0f));
      }
    parents = std::move(children);
  }
  data.add("productNodeRects", rects);
  data.add("productNodeCenters", centers);
  data.add("productGridCenters", grid.centers);
  data.define("PRODUCT_WIDTH", product.width);
  data.define("PRODUCT_ROWS", product.rows);
  data.define("PRODUCT_TEXELS_PER_NODE", product.texelsPerNode);
  data.define("PRODUCT_REFINE_DEPTH", std::to_string(levels.size() - 1));  // for #if: no u suffix
  data.define("PRODUCT_GRID_WIDTH", grid.width);
  data.define("PRODUCT_GRID_ROWS", grid.rows);
  data.define("PRODUCT_DEFENSIVE", std::to_string(kEnvProductDefensive));
  return data;
}

}  // namespace iblx
