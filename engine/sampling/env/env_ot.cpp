// The texel-exact OT sampler's mesh and CPU twin (env_ot.h).
#include "engine/sampling/env/env_ot.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"
#include "engine/sampling/env/env_cdf.h"
#include "engine/sampling/env/env_ot_maps.h"
#include "engine/sampling/float_cdf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace iblx {
namespace {

// A horizontal band of the parameter square inside one texel row and one OT density row, where both the
// parameter's y and the texel's t.y are affine in cos(theta).
struct Band {
  double y0 = 0.0, y1 = 0.0;  // parameter y range
  int texelRow = 0, densityRow = 0;
  bool wholeTexelRow = false;        // the band spans its texel row entirely
  double tyAt0 = 0.0, tyPerY = 0.0;  // t.y = tyAt0 + tyPerY * (y - y0)
};

// The parameter y of latitude v = theta / pi (otDirectionToParameter): row r = floor(v n), linear in
// cos(theta) inside the row. Exact at the density rows' edges.
double parameterOfLatitude(long long numerator, long long denominator, int n) {
  const long long scaled = numerator * n;
  if (scaled % denominator == 0) return double(scaled / denominator) / n;
  const long long r = scaled / denominator;
  const double v = double(numerator) / double(denominator);
  return (double(r) +
          cosDifferenceOfV(double(r) / n, v) / cosDifferenceOfV(double(r) / n, double(r + 1) / n)) /
         n;
}

std::vector<Band> makeBands(int height, int n) {
  std::vector<double> edges;
  std::vector<double> texelEdges(std::size_t(height) + 1);
  for (int y = 0; y <= height; ++y) texelEdges[std::size_t(y)] = parameterOfLatitude(y, height, n);
  edges = texelEdges;
  for (int r = 0; r <= n; ++r) edges.push_back(double(r) / n);
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<Band> bands;
  for (std::size_t k = 0; k + 1 < edges.size(); ++k) {
    Band band;
    band.y0 = edges[k];
    band.y1 = edges[k + 1];
    const double mid = 0.5 * (band.y0 + band.y1);
    band.densityRow = std::min(int(mid * n), n - 1);
    band.texelRow = int(std::upper_bound(texelEdges.begin(), texelEdges.end(), mid) - texelEdges.begin()) - 1;
    band.texelRow = std::clamp(band.texelRow, 0, height - 1);
    const int y = band.texelRow, r = band.densityRow;
    band.wholeTexelRow = band.y0 == texelEdges[std::size_t(y)] && band.y1 == texelEdges[std::size_t(y) + 1];
    // cos(theta_y0) - cos(theta(p)) = [cos(theta_y0) - cos(theta_r0)] + (p n - r) [cos(theta_r0) -
    // cos(theta_r1)].
    const double texelSpan = cosDifferenceOfV(double(y) / height, double(y + 1) / height);
    const double rowSpan = cosDifferenceOfV(double(r) / n, double(r + 1) / n);
    const double offset = cosDifferenceOfV(double(y) / height, double(r) / n);
    band.tyAt0 = (offset + (band.y0 * n - r) * rowSpan) / texelSpan;
    band.tyPerY = n * rowSpan / texelSpan;
    bands.push_back(band);
  }
  return bands;
}

using Polygon = std::vector<glm::dvec2>;

// The point of segment ab on the line p[axis] = value, computed from the endpoints in a fixed order so that
// both triangles sharing an edge get the same point bit for bit.
glm::dvec2 cutAt(glm::dvec2 a, glm::dvec2 b, int axis, double value) {
  if (b.x < a.x || (b.x == a.x && b.y < a.y)) std::swap(a, b);
  const double t = (value - a[axis]) / (b[axis] - a[axis]);
  glm::dvec2 p = a + t * (b - a);
  p[axis] = value;
  return p;
}

// Sutherland-Hodgman against the half-plane sign * (p[axis] - value) >= 0.
Polygon clip(const Polygon& in, int axis, double value, double sign) {
  Polygon out;
  const std::size_t count = in.size();
  for (std::size_t k = 0; k < count; ++k) {
    const glm::dvec2 a = in[k], b = in[(k + 1) % count];
    const bool aIn = sign * (a[axis] - value) >= 0.0, bIn = sign * (b[axis] - value) >= 0.0;
    if (aIn) out.push_back(a);
    if (aIn != bIn) out.push_back(cutAt(a, b, axis, value));
  }
  return out;
}

double signedArea(const Polygon& p) {
  double twice = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const glm::dvec2 a = p[k], b = p[(k + 1) % p.size()];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * twice;
}

std::uint32_t packUnorm2x16(glm::dvec2 t) {
  const auto q = [](double v) { return std::uint32_t(std::lround(std::clamp(v, 0.0, 1.0) * 65535.0)); };
  return q(t.x) | q(t.y) << 16;
}
glm::vec2 unpackUnorm2x16(std::uint32_t v) {
  return {float(v & 0xffffu) / 65535.0f, float(v >> 16) / 65535.0f};
}

// Twice the area of a packed triangle, in texel units.
double packedTriangleArea(const glm::uvec4& piece) {
  const glm::dvec2 a(unpackUnorm2x16(piece.y)), b(unpackUnorm2x16(piece.z)), c(unpackUnorm2x16(piece.w));
  return std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
}

double pieceArea(const glm::uvec4& piece) {
  return (piece.x & kEnvOtTrianglePiece) ? 0.5 * packedTriangleArea(piece) : 1.0;
}

}  // namespace

EnvOtData buildEnvOtMesh(std::span<const double> weights, int width, int height, const OtSunSplit& sun,
                         const QuadGridMap& inverse, int densityGrid) {
  const std::size_t texels = std::size_t(width) * std::size_t(height);
  if (width <= 0 || height <= 0 || weights.size() != texels || sun.smoothWeights.size() != texels ||
      densityGrid < 1)
    throw Error("env-ot: the weights, the sun split and the map's size disagree");
  if (inverse.invalidPieces() > 0)
    throw Error("env-ot: " + std::to_string(inverse.invalidPieces()) +
                " quads of the OT map are not injective; the sampler would not be exact");
  const int n = inverse.size(), densityRows = densityGrid;
  const std::vector<Band> bands = makeBands(height, densityRows);
  std::vector<double> bandEdges;
  for (const Band& b : bands) bandEdges.push_back(b.y0);

  EnvOtData data;
  data.width = width;
  data.height = height;
  data.grid = n;
  data.sunTexels = sun.sunShare > 0.0f ? int(sun.texels.size()) : 0;

  // Pieces, cell by cell; the probability of a piece is fixed once every texel's coverage is known.
  struct PieceGeometry {
    glm::uvec4 record;
    double area;
  };
  std::vector<PieceGeometry> geometry;
  std::vector<std::uint32_t> cellFirst{0};
  std::vector<double> coverage(texels, 0.0);
  const std::span<const glm::dvec2> vertices = inverse.image();
  const auto vertex = [&](int i, int j) { return vertices[std::size_t(j) * (n + 1) + std::size_t(i)]; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec2 p00 = vertex(i, j), p10 = vertex(i + 1, j), p11 = vertex(i + 1, j + 1),
                       p01 = vertex(i, j + 1);
      // A strictly convex quad is one convex polygon; a non-convex one splits along the diagonal through its
      // reflex corner (engine/ot/map.h), so both triangles keep a positive area. Straight edges between
      // shared vertices keep the cells a partition of the parameter square.
      const QuadPiece type = inverse.pieces()[std::size_t(j) * n + i];
      std::vector<Polygon> polygons;
      if (type == QuadPiece::Bilinear)
        polygons = {{p00, p10, p11, p01}};
      else if (type == QuadPiece::SplitAntiDiagonal)
        polygons = {{p00, p10, p01}, {p10, p11, p01}};
      else
        polygons = {{p00, p10, p11}, {p00, p11, p01}};
      for (const Polygon& polygon : polygons) {
        double minX = 1.0, maxX = 0.0, minY = 1.0, maxY = 0.0;
        for (const glm::dvec2 p : polygon) {
          minX = std::min(minX, p.x), maxX = std::max(maxX, p.x);
          minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
        }
        const int column0 = std::clamp(int(std::floor(minX * width)), 0, width - 1);
        const int column1 = std::clamp(int(std::floor(maxX * width)), 0, width - 1);
        const std::size_t band0 = std::size_t(std::max<std::ptrdiff_t>(
            0, std::upper_bound(bandEdges.begin(), bandEdges.end(), minY) - bandEdges.begin() - 1));
        const std::size_t band1 = std::size_t(std::max<std::ptrdiff_t>(
            0, std::upper_bound(bandEdges.begin(), bandEdges.end(), maxY) - bandEdges.begin() - 1));
        for (std::size_t b = band0; b <= band1 && b < bands.size(); ++b) {
          const Band& band = bands[b];
          const Polygon rowPart = clip(clip(polygon, 1, band.y0, 1.0), 1, band.y1, -1.0);
          if (rowPart.size() < 3) continue;
          for (int x = column0; x <= column1; ++x) {
            const double x0 = double(x) / width, x1 = double(x + 1) / width;
            const Polygon part = clip(clip(rowPart, 0, x0, 1.0), 0, x1, -1.0);
            if (part.size() < 3) continue;
            const double area = std::abs(signedArea(part));
            if (!(area > 0.0)) continue;
            const std::uint32_t texel =
                std::uint32_t(band.texelRow) * std::uint32_t(width) + std::uint32_t(x);
            const double rectArea = (x1 - x0) * (band.y1 - band.y0);
            if (band.wholeTexelRow && area >= rectArea * (1.0 - 1e-12)) {
              geometry.push_back({glm::uvec4(texel, 0u, 0u, 0u), 1.0});
              coverage[texel] += 1.0;
              continue;
            }
            const auto toTexel = [&](glm::dvec2 p) {
              return glm::dvec2(p.x * width - x, band.tyAt0 + band.tyPerY * (p.y - band.y0));
            };
            const glm::dvec2 a = toTexel(part[0]);
            for (std::size_t k = 1; k + 1 < part.size(); ++k) {
              const glm::uvec4 record(texel | kEnvOtTrianglePiece, packUnorm2x16(a),
                                      packUnorm2x16(toTexel(part[k])), packUnorm2x16(toTexel(part[k + 1])));
              const double pieceArea = 0.5 * packedTriangleArea(record);
              if (!(pieceArea > 0.0)) continue;
              geometry.push_back({record, pieceArea});
              coverage[texel] += pieceArea;
            }
          }
        }
      }
      cellFirst.push_back(std::uint32_t(geometry.size()));
    }

  double total = 0.0;
  for (std::size_t t = 0; t < texels; ++t) {
    total += weights[t];
    if (sun.smoothWeights[t] > 0.0 && !(coverage[t] > 0.0))
      throw Error("env-ot: texel " + std::to_string(t) + " is not covered by the OT map's triangles");
  }
  if (!(total > 0.0)) throw Error("env-ot: the environment has no weight");

  // Masses: a texel's smooth weight split over its pieces by area; pieces of zero mass are dropped. A row's
  // pieces are ordered by cell, so one CDF over them is the cell CDF followed by each cell's piece CDF. The
  // sun part, when split, is one more row of whole sun texels with their excess weight: its share of u.y is a
  // strip of the same 2D sample, and sampling takes one path for both parts.
  const bool sunRow = sun.sunShare > 0.0f;
  data.rows = n + (sunRow ? 1 : 0);
  std::vector<double> rowMass(std::size_t(data.rows), 0.0), masses;
  std::uint32_t guideFirst = 0;
  const auto endRow = [&](std::size_t j) {
    const std::size_t count = masses.size();
    for (const double m : masses) rowMass[j] += m;
    const std::size_t cdfStart = data.pieceCdf.size();
    data.pieceCdf.resize(cdfStart + count + 1);
    writeFloatCdf(masses, data.pieceCdf.data() + cdfStart);
    const int cells = envCdfGuideCells(int(std::max<std::size_t>(count, 1)), 1);
    data.pieceGuide.resize(guideFirst + std::size_t(cells));
    if (count > 0)
      writeGuide(data.pieceCdf.data() + cdfStart, int(count), cells, data.pieceGuide.data() + guideFirst);
    data.rowPieces.push_back(
        glm::uvec4(std::uint32_t(data.pieces.size() - count), guideFirst, std::uint32_t(cells), 0u));
    guideFirst += std::uint32_t(cells);
    masses.clear();
  };
  for (int j = 0; j < n; ++j) {
    for (std::size_t c = std::size_t(j) * n; c < std::size_t(j + 1) * n; ++c)
      for (std::uint32_t k = cellFirst[c]; k < cellFirst[c + 1]; ++k) {
        const std::uint32_t texel = geometry[k].record.x & ~kEnvOtTrianglePiece;
        const double mass = sun.smoothWeights[texel] / total * geometry[k].area / coverage[texel];
        if (!(mass > 0.0)) continue;
        data.pieces.push_back(geometry[k].record);
        masses.push_back(mass);
      }
    endRow(std::size_t(j));
  }
  if (sunRow) {
    for (const std::uint32_t texel : sun.texels) {
      const double mass = (weights[texel] - sun.smoothWeights[texel]) / total;
      if (!(mass > 0.0)) continue;
      data.pieces.push_back(glm::uvec4(texel, 0u, 0u, 0u));
      masses.push_back(mass);
    }
    endRow(std::size_t(n));
  }
  data.rowPieces.push_back(glm::uvec4(std::uint32_t(data.pieces.size()), guideFirst, 0u, 0u));
  data.rowCdf.resize(std::size_t(data.rows) + 1);
  writeFloatCdf(rowMass, data.rowCdf.data());
  data.rowGuideCells = envCdfGuideCells(data.rows, 2);
  data.rowGuide.resize(std::size_t(data.rowGuideCells));
  writeGuide(data.rowCdf.data(), data.rows, data.rowGuideCells, data.rowGuide.data());

  // The pdf is the probability the float tables give each texel (the sum over its pieces), over its solid
  // angle: what sampling draws, so the estimator has no bias from the CDFs' rounding (as env-cdf's).
  std::vector<double> probability(texels, 0.0);
  for (int j = 0; j < data.rows; ++j) {
    const double rowProb = double(data.rowCdf[std::size_t(j) + 1] - data.rowCdf[std::size_t(j)]);
    const std::uint32_t first = data.rowPieces[std::size_t(j)].x, end = data.rowPieces[std::size_t(j) + 1].x;
    const float* cdf = data.pieceCdf.data() + first + std::size_t(j);
    for (std::uint32_t k = 0; k < end - first; ++k)
      probability[data.pieces[first + k].x & ~kEnvOtTrianglePiece] += rowProb * double(cdf[k + 1] - cdf[k]);
  }
  data.texelPdf.resize(texels);
  for (int y = 0; y < height; ++y) {
    const double omega = latLongTexelSolidAngle(y, width, height);
    for (int x = 0; x < width; ++x) {
      const std::size_t t = std::size_t(y) * width + x;
      data.texelPdf[t] = float(probability[t] / omega);
    }
  }
  return data;
}

EnvOtData buildEnvOt(const EnvImage& image) {
  const EnvOtMaps maps = solveEnvOtMaps(image, envOtGridSize(image));
  const QuadGridMap inverse = tabulatedInverse(forwardMap(maps.map), maps.map.n);
  return buildEnvOtMesh(maps.weights, image.width, image.height, maps.sun, inverse, maps.map.n);
}

EnvOtSampler::EnvOtSampler(EnvOtData data) : data_(std::move(data)) {
  const EnvOtData& d = data_;
  const std::size_t rows = std::size_t(d.rows), texels = std::size_t(d.width) * std::size_t(d.height);
  bool valid = d.grid >= 1 && (rows == std::size_t(d.grid) || rows == std::size_t(d.grid) + 1) &&
               d.rowCdf.size() == rows + 1 && d.rowPieces.size() == rows + 1 && d.rowGuideCells >= 1 &&
               d.rowGuide.size() == std::size_t(d.rowGuideCells) && d.texelPdf.size() == texels &&
               d.pieceCdf.size() == d.pieces.size() + rows && d.rowPieces.back().x == d.pieces.size() &&
               d.rowPieces.back().y == d.pieceGuide.size();
  for (std::size_t j = 0; valid && j < rows; ++j)
    valid = d.rowPieces[j].x <= d.rowPieces[j + 1].x && d.rowPieces[j].z >= 1 &&
            d.rowPieces[j].y + d.rowPieces[j].z == d.rowPieces[j + 1].y;
  if (!valid) throw Error("env-ot: the tables' sizes do not match the grid and the map");
  std::vector<std::uint32_t> counts(texels + 1, 0);
  for (const glm::uvec4& piece : d.pieces) {
    const std::uint32_t texel = piece.x & ~kEnvOtTrianglePiece;
    if (texel >= texels) throw Error("env-ot: a piece names a texel outside the map");
    ++counts[texel + 1];
  }
  for (std::size_t t = 0; t < texels; ++t) counts[t + 1] += counts[t];
  texelPieceFirst_ = counts;
  texelPieces_.resize(d.pieces.size());
  for (std::uint32_t k = 0; k < d.pieces.size(); ++k)
    texelPieces_[counts[d.pieces[k].x & ~kEnvOtTrianglePiece]++] = k;
}

EnvSample EnvOtSampler::sample(glm::dvec2 uIn) const {
  const EnvOtData& d = data_;
  const float ux = toGpuU(uIn.x), uy = toGpuU(uIn.y);
  EnvSample s;
  const std::size_t j = std::size_t(findBinGuided(d.rowCdf.data(), d.rowGuide.data(), d.rowGuideCells, uy));
  const float ry = remapInFloatBin(uy, d.rowCdf[j], d.rowCdf[j + 1] - d.rowCdf[j]);
  const glm::uvec4 row = d.rowPieces[j];
  const std::size_t first = row.x, count = d.rowPieces[j + 1].x - first;
  if (count == 0) return s;  // a row of zero mass is never chosen; the guard keeps the code total
  const float* cdf = d.pieceCdf.data() + first + j;
  const std::size_t k = std::size_t(findBinGuided(cdf, d.pieceGuide.data() + row.y, int(row.z), ux));
  const float sx = remapInFloatBin(ux, cdf[k], cdf[k + 1] - cdf[k]);
  const glm::uvec4 piece = d.pieces[first + k];
  const std::uint32_t index = piece.x & ~kEnvOtTrianglePiece;
  glm::vec2 t{sx, ry};
  if (piece.x & kEnvOtTrianglePiece) {
    const float root = std::sqrt(sx);
    t = (1.0f - root) * unpackUnorm2x16(piece.y) + root * (1.0f - ry) * unpackUnorm2x16(piece.z) +
        (root * ry) * unpackUnorm2x16(piece.w);
  }
  s.texel = {int(index % std::uint32_t(d.width)), int(index / std::uint32_t(d.width))};
  s.direction = texelToDirection(s.texel.x, s.texel.y, glm::dvec2(t), d.width, d.height);
  s.pdfSolidAngle = d.texelPdf[index];
  return s;
}

double EnvOtSampler::pdf(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return 0.0;
  const glm::ivec2 texel = directionToTexel(wi, data_.width, data_.height);
  return data_.texelPdf[std::size_t(texel.y) * data_.width + texel.x];
}

std::uint32_t EnvOtSampler::pieceRow(std::uint32_t piece) const {
  const auto after = std::upper_bound(data_.rowPieces.begin(), data_.rowPieces.end(), piece,
                                      [](std::uint32_t p, const glm::uvec4& row) { return p < row.x; });
  return std::uint32_t(after - data_.rowPieces.begin()) - 1;
}

double EnvOtSampler::pieceProbability(std::uint32_t piece) const {
  const EnvOtData& d = data_;
  const std::uint32_t j = pieceRow(piece);
  const float* cdf = d.pieceCdf.data() + piece + j;
  return double(d.rowCdf[j + 1] - d.rowCdf[j]) * double(cdf[1] - cdf[0]);
}

double EnvOtSampler::texelProbability(int x, int y) const {
  const std::size_t texel = std::size_t(y) * data_.width + x;
  double probability = 0.0;
  for (std::uint32_t k = texelPieceFirst_[texel]; k < texelPieceFirst_[texel + 1]; ++k)
    probability += pieceProbability(texelPieces_[k]);
  return probability;
}

double EnvOtSampler::texelCoverage(int x, int y) const {
  const std::size_t texel = std::size_t(y) * data_.width + x;
  double area = 0.0;
  for (std::uint32_t k = texelPieceFirst_[texel]; k < texelPieceFirst_[texel + 1]; ++k) {
    const std::uint32_t piece = texelPieces_[k];
    if (pieceRow(piece) < std::uint32_t(data_.grid)) area += pieceArea(data_.pieces[piece]);
  }
  return area;
}

std::optional<glm::dvec2> EnvOtSampler::invert(glm::dvec3 wi) const {
  if (!isUsableDirection(wi)) return std::nullopt;
  const EnvOtData& d = data_;
  const glm::ivec2 texel = directionToTexel(wi, d.width, d.height);
  const std::size_t index = std::size_t(texel.y) * d.width + texel.x;
  const glm::dvec2 t = directionToTexelOffset(wi, texel, d.width, d.height);
  // The piece that holds t best: a whole texel (the map's or the sun row's), else the triangle whose smallest
  // barycentric coordinate is the largest.
  std::optional<std::uint32_t> best;
  glm::dvec3 bestBary(0.0);
  double bestInside = -1e300;
  for (std::uint32_t k = texelPieceFirst_[index]; k < texelPieceFirst_[index + 1]; ++k) {
    const std::uint32_t p = texelPieces_[k];
    if (!(pieceProbability(p) > 0.0)) continue;
    const glm::uvec4 piece = d.pieces[p];
    if (!(piece.x & kEnvOtTrianglePiece)) {
      best = p;
      break;
    }
    const glm::dvec2 a(unpackUnorm2x16(piece.y)), b(unpackUnorm2x16(piece.z)), c(unpackUnorm2x16(piece.w));
    const double det = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    const double beta = ((t.x - a.x) * (c.y - a.y) - (t.y - a.y) * (c.x - a.x)) / det;
    const double gamma = ((b.x - a.x) * (t.y - a.y) - (b.y - a.y) * (t.x - a.x)) / det;
    const glm::dvec3 bary(1.0 - beta - gamma, beta, gamma);
    const double inside = std::min({bary.x, bary.y, bary.z});
    if (inside > bestInside) bestInside = inside, best = p, bestBary = bary;
  }
  if (!best) return std::nullopt;
  const std::uint32_t p = *best, j = pieceRow(p);
  glm::dvec2 local = t;                       // (sx, ry)
  if (d.pieces[p].x & kEnvOtTrianglePiece) {  // inverse of Osada et al.'s map: sqrt(r1) = 1 - alpha
    const glm::dvec3 bary = glm::clamp(bestBary, 0.0, 1.0);
    const double root = std::clamp(1.0 - bary.x, 0.0, 1.0);
    local = {root * root, root > 0.0 ? std::clamp(bary.z / root, 0.0, 1.0) : 0.0};
  }
  const float* cdf = d.pieceCdf.data() + p + j;
  return glm::dvec2(cdf[0] + local.x * double(cdf[1] - cdf[0]),
                    d.rowCdf[j] + local.y * double(d.rowCdf[j + 1] - d.rowCdf[j]));
}

TechniqueData envOtTechniqueData(const EnvOtData& d) {
  TechniqueData data;
  data.add("envOtRowCdf", d.rowCdf);
  data.add("envOtRowGuide", d.rowGuide);
  data.add("envOtRow", d.rowPieces);
  data.add("envOtPieceCdf", d.pieceCdf);
  data.add("envOtPieceGuide", d.pieceGuide);
  data.add("envOtPiece", d.pieces);
  data.add("envOtTexelPdf", d.texelPdf);
  data.define("ENV_OT_ROW_GUIDE_SIZE", std::uint32_t(d.rowGuideCells));
  return data;
}

TechniqueData envOtTechniqueData(const EnvImage& image) {
  return envOtTechniqueData(buildEnvOt(image));
}

}  // namespace iblx
