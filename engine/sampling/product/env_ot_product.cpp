// Warp composition over env-ot's unit square: env-ot's inverse tables, the head grid and the CPU twin.
#include "engine/sampling/product/env_ot_product.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"
#include "engine/io/latlong_texel.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace iblx {
namespace {

glm::dvec2 unpackCorner(
    std::uint32_t v) {  // GLSL unpackUnorm2x16, as engine/sampling/env/env_ot.cpp packs the corners
  return {double(float(v & 0xffffu) / 65535.0f), double(float(v >> 16) / 65535.0f)};
}

// Probability (float tables, in double) of piece p of row j: the row's CDF width times the piece's.
double pieceProbability(const EnvOtData& d, std::uint32_t p, std::uint32_t j) {
  const float* cdf = d.pieceCdf.data() + p + j;
  return double(d.rowCdf[j + 1] - d.rowCdf[j]) * double(cdf[1] - cdf[0]);
}

// u of the point `local` (the rescaled (u.x, u.y) the piece was placed with) of entry (piece, row).
glm::dvec2 pieceToU(const EnvOtData& d, glm::uvec2 entry, glm::dvec2 local) {
  const float* cdf = d.pieceCdf.data() + entry.x + entry.y;
  return {double(cdf[0]) + local.x * double(cdf[1] - cdf[0]),
          double(d.rowCdf[entry.y]) + local.y * double(d.rowCdf[entry.y + 1] - d.rowCdf[entry.y])};
}

}  // namespace

EnvOtInverse buildEnvOtInverse(const EnvOtData& d) {
  const std::size_t texels = std::size_t(d.width) * std::size_t(d.height);
  if (d.texelPdf.size() != texels || d.rowPieces.size() != std::size_t(d.rows) + 1)
    throw Error("env-ot inverse: the tables do not match the map's size");
  EnvOtInverse inv;
  inv.width = d.width;
  inv.height = d.height;
  inv.grid = d.grid;
  // Per texel, its entries in piece order: the map's rows come before the sun row, so the sun piece is last.
  std::vector<std::vector<glm::uvec2>> perTexel(texels);
  std::vector<double> mapProbability(texels, 0.0), sunProbability(texels, 0.0);
  for (std::uint32_t j = 0; j < std::uint32_t(d.rows); ++j)
    for (std::uint32_t p = d.rowPieces[j].x; p < d.rowPieces[j + 1].x; ++p) {
      const double probability = pieceProbability(d, p, j);
      if (!(probability > 0.0)) continue;  // never sampled: no preimage there
      const std::uint32_t texel = d.pieces[p].x & ~kEnvOtTrianglePiece;
      if (texel >= texels) throw Error("env-ot inverse: a piece names a texel outside the map");
      perTexel[texel].emplace_back(p, j);
      (j < std::uint32_t(d.grid) ? mapProbability : sunProbability)[texel] += probability;
    }
  inv.texelFirst.reserve(texels + 1);
  inv.branchPdf.resize(texels);
  for (std::size_t t = 0; t < texels; ++t) {
    inv.texelFirst.push_back(std::uint32_t(inv.entries.size()));
    inv.entries.insert(inv.entries.end(), perTexel[t].begin(), perTexel[t].end());
    const double omega = latLongTexelSolidAngle(int(t / std::size_t(d.width)), d.width, d.height);
    inv.branchPdf[t] = sunProbability[t] > 0.0
                           ? glm::vec2(float(mapProbability[t] / omega), float(sunProbability[t] / omega))
                           : glm::vec2(d.texelPdf[t], 0.0f);
  }
  inv.texelFirst.push_back(std::uint32_t(inv.entries.size()));
  return inv;
}

EnvOtPreimages envOtPreimages(const EnvOtData& d, const EnvOtInverse& inv, glm::dvec3 wi) {
  EnvOtPreimages result;
  if (!isUsableDirection(wi)) return result;
  const glm::ivec2 texel = directionToTexel(wi, d.width, d.height);
  const std::size_t index = std::size_t(texel.y) * std::size_t(d.width) + std::size_t(texel.x);
  const glm::dvec2 t = directionToTexelOffset(wi, texel, d.width, d.height);
  result.mapPdf = double(inv.branchPdf[index].x);
  result.sunPdf = double(inv.branchPdf[index].y);
  // The map's piece that holds t: a whole texel, else the first triangle that holds t (the pieces tile the
  // texel), else, t being on an edge within rounding, the triangle whose smallest barycentric coordinate is
  // the largest (EnvOtSampler::invert's choice).
  std::optional<glm::uvec2> best;
  glm::dvec2 bestLocal(0.0);
  double bestInside = -1e300;
  std::uint32_t end = inv.texelFirst[index + 1];
  if (end > inv.texelFirst[index] && inv.entries[end - 1].y >= std::uint32_t(d.grid))
    result.sun = pieceToU(d, inv.entries[--end], t);  // the sun row's whole texel, the last entry
  for (std::uint32_t e = inv.texelFirst[index]; e < end && bestInside < 0.0; ++e) {
    const glm::uvec2 entry = inv.entries[e];
    const glm::uvec4 piece = d.pieces[entry.x];
    if (!(piece.x & kEnvOtTrianglePiece)) {
      best = entry, bestLocal = t, bestInside = 1.0;
      break;
    }
    const glm::dvec2 a = unpackCorner(piece.y), b = unpackCorner(piece.z), c = unpackCorner(piece.w);
    const double det = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(det != 0.0)) continue;
    const double beta = ((t.x - a.x) * (c.y - a.y) - (t.y - a.y) * (c.x - a.x)) / det;
    const double gamma = ((b.x - a.x) * (t.y - a.y) - (b.y - a.y) * (t.x - a.x)) / det;
    const double inside = std::min({1.0 - beta - gamma, beta, gamma});
    if (inside > bestInside) {
      // The inverse of Osada et al.'s map: sqrt(r1) = 1 - alpha = beta + gamma, r2 = gamma / sqrt(r1).
      const double root = std::clamp(beta + gamma, 0.0, 1.0);
      bestLocal = {root * root, root > 0.0 ? std::clamp(gamma / root, 0.0, 1.0) : 0.0};
      bestInside = inside, best = entry;
    }
  }
  if (best) result.map = pieceToU(d, *best, bestLocal);
  return result;
}

EnvOtProductSampler::EnvOtProductSampler(const EnvOtSampler& env, const EnvOtInverse& inverse,
                                         const EnvProductLevel& grid, std::span<const double> fCos)
    : env_(env),
      inverse_(inverse),
      grid_(grid),
      probability_(quantizedNodeProbabilities(grid, envProductWeights(grid, fCos))),
      cells_(probability_, int(grid.width), int(grid.rows)) {
  if (!grid.uniformGrid) throw Error("env-ot product sampler: the head is a uniform grid over u");
}

std::size_t EnvOtProductSampler::cellOf(glm::dvec2 u) const {
  const auto clampedFloor = [](double v, uint32_t n) {
    return std::size_t(std::clamp(std::floor(v * n), 0.0, double(n - 1)));
  };
  return clampedFloor(u.y, grid_.rows) * grid_.width + clampedFloor(u.x, grid_.width);
}

double EnvOtProductSampler::headDensity(glm::dvec2 u) const {
  const std::size_t j = cellOf(u);
  const glm::vec4& r = grid_.rects[j];
  const double area = double((r.z - r.x) * (r.w - r.y));
  return area > 0.0 ? probability_[j] / area : 0.0;
}

double EnvOtProductSampler::composedPdf(glm::dvec3 wi, std::optional<std::pair<bool, double>> taken) const {
  const EnvOtPreimages pre = envOtPreimages(env_.data(), inverse_, wi);
  const auto branch = [&](bool sun, const std::optional<glm::dvec2>& u, double q) {
    if (!(q > 0.0)) return 0.0;
    if (taken && taken->first == sun) return taken->second * q;
    return u ? headDensity(*u) * q : 0.0;
  };
  return branch(false, pre.map, pre.mapPdf) + branch(true, pre.sun, pre.sunPdf);
}

EnvSample EnvOtProductSampler::sample(glm::dvec2 u) const {
  const PiecewiseConstant2D::Sample chosen = cells_.sample(u);
  const std::size_t j = std::size_t(chosen.bin.y) * grid_.width + std::size_t(chosen.bin.x);
  if (!(probability_[j] > 0.0)) return {};  // an all-zero table: no cell to choose
  const glm::vec4& r = grid_.rects[j];
  const glm::dvec2 inCell = pointInProductNode(chosen, grid_, j);
  EnvSample s = env_.sample(inCell);
  const double area = double((r.z - r.x) * (r.w - r.y));
  if (!(s.pdfSolidAngle > 0.0) || !(area > 0.0)) {
    s.pdfSolidAngle = 0.0;
    return s;
  }
  const double head = probability_[j] / area;
  const std::size_t texel = std::size_t(s.texel.y) * std::size_t(env_.data().width) + std::size_t(s.texel.x);
  if (!(inverse_.branchPdf[texel].y > 0.0f)) {  // one preimage: h(u) p_env-ot
    s.pdfSolidAngle = head * s.pdfSolidAngle;
    return s;
  }
  // A sun texel: the branch taken is the sun row when u.y reached it (env-ot's row search).
  const EnvOtData& d = env_.data();
  const bool sunRow = d.rows > d.grid && toGpuU(inCell.y) >= d.rowCdf[std::size_t(d.grid)];
  s.pdfSolidAngle = composedPdf(s.direction, std::pair{sunRow, head});
  return s;
}

double EnvOtProductSampler::pdf(glm::dvec3 wi) const {
  return composedPdf(wi, std::nullopt);
}

EnvProductLevel buildEnvOtProductGrid(const EnvOtSampler& env, uint32_t width, uint32_t rows) {
  const double texel = std::max(2.0 * kPi / env.data().width, kPi / env.data().height);
  return buildEnvProductGrid([&env](glm::dvec2 u) { return env.sample(u).direction; }, texel, width, rows);
}

TechniqueData envOtProductTechniqueData(const EnvOtData& d) {
  TechniqueData data = envOtTechniqueData(d);
  const EnvOtInverse inverse = buildEnvOtInverse(d);
  const EnvOtSampler sampler(d);
  const EnvProductLevel grid = buildEnvOtProductGrid(sampler);
  data.add("envOtTexelEntryFirst", inverse.texelFirst);
  data.add("envOtTexelEntry", inverse.entries);
  data.add("envOtBranchPdf", inverse.branchPdf);
  data.add("productGridCenters", grid.centers);
  data.define("ENV_OT_GRID", std::uint32_t(d.grid));
  data.define("PRODUCT_TAIL_ENV_OT", "1");
  data.define("PRODUCT_GRID_WIDTH", grid.width);
  data.define("PRODUCT_GRID_ROWS", grid.rows);
  data.define("PRODUCT_DEFENSIVE", std::to_string(kEnvProductDefensive));
  return data;
}

TechniqueData envOtProductTechniqueData(const EnvImage& image) {
  return envOtProductTechniqueData(buildEnvOt(image));
}

}  // namespace iblx
