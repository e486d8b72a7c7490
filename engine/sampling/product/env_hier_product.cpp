// env-hier product level: the level's node rectangles and centres, and the CPU twin of the product sampler.
#include "engine/sampling/product/env_hier_product.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace iblx {
EnvProductLevel buildEnvProductLevel(const EnvHierSampler& env, uint32_t maxNodes) {
  if (maxNodes == 0) throw Error("env-hier product level: at least one node is needed");
  const EnvHierData& data = env.data();
  const uint32_t finest = uint32_t(data.levels.size() - 1), size = data.levels.back().width;
  // Nodes across and node rows that hold texels at level k.
  auto extent = [&](uint32_t k) {
    const uint32_t width = 1u << k, per = size >> k;
    return std::pair{width, (uint32_t(data.height) + per - 1) / per};
  };
  uint32_t level = 0;
  for (uint32_t k = 0; k <= finest; ++k) {
    const auto [width, rows] = extent(k);
    if (uint64_t(width) * rows <= maxNodes) level = k;
  }
  EnvProductLevel l;
  std::tie(l.width, l.rows) = extent(level);
  l.texelsPerNode = size >> level;
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

EnvProductSampler::EnvProductSampler(const EnvHierSampler& env, const EnvProductLevel& level,
                                     std::span<const double> fCos)
    : EnvProductSampler(FromWeights{}, env, level, envProductWeights(level, fCos)) {}

EnvProductSampler::EnvProductSampler(FromWeights, const EnvHierSampler& env, const EnvProductLevel& level,
                                     std::vector<double> weights)
    : env_(env),
      level_(level),
      probability_(quantizedNodeProbabilities(level, weights)),
      nodes_(probability_, int(level.width), int(level.rows)) {}

std::size_t EnvProductSampler::nodeOf(glm::dvec3 wi) const {
  if (level_.uniformGrid) {
    const glm::dvec2 u = env_.invert(wi).value_or(glm::dvec2(0.0));
    return std::min(std::size_t(u.y * level_.rows), std::size_t(level_.rows - 1)) * level_.width +
           std::min(std::size_t(u.x * level_.width), std::size_t(level_.width - 1));
  }
  const glm::ivec2 texel = directionToTexel(wi, env_.data().width, env_.data().height);
  return std::size_t(uint32_t(texel.y) / level_.texelsPerNode) * level_.width +
         uint32_t(texel.x) / level_.texelsPerNode;
}

glm::dvec2 pointInProductNode(const PiecewiseConstant2D::Sample& chosen, const EnvProductLevel& level,
                              std::size_t j) {
  const glm::dvec2 v = glm::clamp(chosen.p * glm::dvec2(level.width, level.rows) - glm::dvec2(chosen.bin),
                                  glm::dvec2(0.0), glm::dvec2(1.0));
  const glm::vec4& r = level.rects[j];
  return {std::clamp(double(r.x) + v.x * double(r.z - r.x), double(r.x), double(std::nextafter(r.z, r.x))),
          std::clamp(double(r.y) + v.y * double(r.w - r.y), double(r.y), double(std::nextafter(r.w, r.y)))};
}

EnvSample EnvProductSampler::sample(glm::dvec2 u) const {
  const PiecewiseConstant2D::Sample chosen = nodes_.sample(u);
  const std::size_t j = std::size_t(chosen.bin.y) * level_.width + std::size_t(chosen.bin.x);
  if (!(probability_[j] > 0.0)) return {};  // an all-zero table: no node to choose
  const glm::vec4& r = level_.rects[j];
  // The chosen node's probability over its area, times env-hier's density inside it.
  EnvSample s = env_.sample(pointInProductNode(chosen, level_, j));
  const double area = double((r.z - r.x) * (r.w - r.y));
  s.pdfSolidAngle = area > 0.0 ? probability_[j] / area * s.pdfSolidAngle : 0.0;
  return s;
}

double EnvProductSampler::pdf(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return 0.0;
  const std::size_t j = nodeOf(wi);
  const glm::vec4& r = level_.rects[j];
  const double area = double((r.z - r.x) * (r.w - r.y));
  return area > 0.0 ? probability_[j] / area * env_.pdf(wi) : 0.0;
}

TechniqueData envHierProductTechniqueData(const EnvImage& image) {
  const EnvHierSampler sampler(buildEnvHier(image));
  TechniqueData data = envHierTechniqueData(sampler);
  const EnvProductLevel product = buildEnvProductLevel(sampler);
  const EnvProductLevel grid = buildEnvProductGrid(sampler);
  for (const EnvProductLevel* level : {&product, &grid})
    if (productTableWords(level->width, level->rows) > kEnvProductMaxTableWords)
      throw Error("env-hier product: a " + std::to_string(level->width) + "x" + std::to_string(level->rows) +
                  " node table does not fit a pixel's stored table of " +
                  std::to_string(kEnvProductMaxTableWords) + " words");
  data.add("productNodeRects", product.rects);
  data.add("productNodeCenters", product.centers);
  data.add("productGridCenters", grid.centers);
  data.define("PRODUCT_WIDTH", product.width);
  data.define("PRODUCT_ROWS", product.rows);
  data.define("PRODUCT_TEXELS_PER_NODE", product.texelsPerNode);
  data.define("PRODUCT_GRID_WIDTH", grid.width);
  data.define("PRODUCT_GRID_ROWS", grid.rows);
  data.define("PRODUCT_DEFENSIVE", std::to_string(kEnvProductDefensive));
  return data;
}

}  // namespace iblx
