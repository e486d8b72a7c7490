// Offline diagnostics of the environment samplers' pdfs (env_ot_diagnostics.h).
#include "engine/sampling/env/env_ot_diagnostics.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"
#include "engine/sampling/env/env_ot_maps.h"
#include "engine/io/latlong_texel.h"
#include "engine/ot/solver.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

namespace iblx {
namespace {

// The corners of cell `cell` of a vertex grid, counter-clockwise (quadGridCorners in quad_grid_map.glsl).
void cellCorners(const QuadGridMap& map, std::size_t cell, glm::dvec2 corners[4]) {
  const std::size_t m = std::size_t(map.size()), i = cell % m, j = cell / m, v = j * (m + 1) + i;
  const auto image = map.image();
  corners[0] = image[v];
  corners[1] = image[v + 1];
  corners[2] = image[v + m + 2];
  corners[3] = image[v + m + 1];
}

// quadMapInvertCell: y's preimage in cell `cell` of `map`, with the Jacobian determinant there (domain
// units); false when y lies outside the cell's piece by more than `tolerance` (local units).
bool invertInCell(const QuadGridMap& map, std::size_t cell, glm::dvec2 y, double tolerance,
                  double& jacobian) {
  glm::dvec2 corners[4];
  cellCorners(map, cell, corners);
  const QuadPiece piece = map.pieces()[cell];
  glm::dvec2 st;
  if (!invertPiece(piece, corners, y, st, tolerance)) return false;
  double local = 0.0;
  evaluatePiece(piece, corners, st, &local);
  jacobian = local * double(map.size()) * double(map.size());
  return true;
}

// The sun part's pdf per unit solid angle at w (otSunTexelPdf): its texel's probability over the texel's
// solid angle, 0 off the sun texels.
double sunPdf(const OtSunSplit& sun, glm::dvec3 w) {
  const glm::ivec2 texel = directionToTexel(w, sun.width, sun.height);
  const double probability = double(sun.texelProbability(texel.x, texel.y));
  return probability > 0.0 ? probability / latLongTexelSolidAngle(texel.y, sun.width, sun.height) : 0.0;
}

// otSunMixture.
double mixture(const OtSunSplit& sun, glm::dvec3 w, double otPdf) {
  const double share = double(sun.sunShare);
  return share * sunPdf(sun, w) + (1.0 - share) * otPdf;
}

// The statistics of |roundTrip(u) - u| over points x points cell centres u; roundTrip empty = not mapped.
template <typename RoundTrip>
MapRoundTrip measureRoundTrip(int points, RoundTrip roundTrip) {
  if (points < 1) throw Error("map round trip: expected at least 1 point per axis");
  MapRoundTrip result;
  double sum = 0.0;
  std::size_t mapped = 0;
  for (int j = 0; j < points; ++j)
    for (int i = 0; i < points; ++i) {
      const glm::dvec2 u((i + 0.5) / points, (j + 0.5) / points);
      const std::optional<glm::dvec2> back = roundTrip(u);
      if (!back) {
        ++result.missed;
        continue;
      }
      const double error = glm::length(*back - u);
      result.max = std::max(result.max, error);
      sum += error;
      ++mapped;
    }
  result.mean = mapped > 0 ? sum / double(mapped) : 0.0;
  return result;
}

}  // namespace

std::vector<double> texelProbabilities(const EnvImage& image) {
  std::vector<double> p = texelSamplingWeights(image, "texel pdf");
  double total = 0.0;
  for (const double w : p) total += w;
  for (double& w : p) w /= total;
  return p;
}

std::vector<double> integrateTexelProbabilities(const std::function<double(glm::dvec3)>& pdf, int width,
                                                int height, int subgrid) {
  if (width < 1 || height < 1 || subgrid < 1)
    throw Error("texel probabilities: expected a positive map size and sub-grid, got " +
                std::to_string(width) + " x " + std::to_string(height) + ", " + std::to_string(subgrid));
  std::vector<double> q(std::size_t(width) * height);
  const double points = double(subgrid) * subgrid;
  for (int y = 0; y < height; ++y) {
    const double omega = latLongTexelSolidAngle(y, width, height);
    for (int x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int b = 0; b < subgrid; ++b)
        for (int a = 0; a < subgrid; ++a) {
          // texelToDirection is uniform in phi and cos(theta): midpoints of t are uniform in solid angle.
          const glm::dvec2 t((a + 0.5) / subgrid, (b + 0.5) / subgrid);
          sum += pdf(texelToDirection(x, y, t, width, height));
        }
      q[std::size_t(y) * width + x] = omega * sum / points;
    }
  }
  return q;
}

TexelChi2 texelChi2(std::span<const double> p, std::span<const double> q) {
  if (p.size() != q.size())
    throw Error("texel chi^2: " + std::to_string(p.size()) + " texel probabilities against " +
                std::to_string(q.size()));
  TexelChi2 result;
  for (std::size_t t = 0; t < p.size(); ++t) {
    if (!(p[t] >= 0.0) || !(q[t] >= 0.0) || !std::isfinite(p[t]) || !std::isfinite(q[t]))
      throw Error("texel chi^2: texel " + std::to_string(t) + " has a negative or non-finite probability");
    result.qMass += q[t];
  }
  if (!(result.qMass > 0.0)) throw Error("texel chi^2: the sampler's probabilities are zero everywhere");
  double sum = 0.0;
  for (std::size_t t = 0; t < p.size(); ++t) {
    if (q[t] > 0.0)
      sum += p[t] * p[t] / (q[t] / result.qMass);
    else
      result.unreachableMass += p[t];
  }
  result.chi2 = sum - 1.0;
  return result;
}

glm::dvec3 otParameterToDirection(glm::dvec2 x, int densityGrid, double& jacobian) {
  const double n = densityGrid;
  const double r = std::min(std::floor(x.y * n), n - 1.0), f = std::clamp(x.y * n - r, 0.0, 1.0);
  const double theta0 = kPi * r / n, theta1 = kPi * (r + 1.0) / n;
  const double rowDelta = cosDifference(theta0, theta1);
  jacobian = 2.0 * kPi * n * rowDelta;
  // 1 - cos(theta) and 1 + cos(theta) each from the nearer pole's side, so neither cancels.
  const double s0 = std::sin(0.5 * theta0), c1 = std::cos(0.5 * theta1);
  const double oneMinusCos = 2.0 * s0 * s0 + f * rowDelta, onePlusCos = 2.0 * c1 * c1 + (1.0 - f) * rowDelta;
  const double cosTheta = x.y < 0.5 ? 1.0 - oneMinusCos : onePlusCos - 1.0;
  const double sinTheta = std::sqrt(std::max(oneMinusCos * onePlusCos, 0.0));
  const double phi = 2.0 * kPi * x.x;
  return {sinTheta * std::cos(phi), cosTheta, sinTheta * std::sin(phi)};
}

glm::dvec2 otDirectionToParameter(glm::dvec3 w, int densityGrid, double& jacobian) {
  const double n = densityGrid;
  const glm::dvec2 latLong = directionToLatLong(w);
  const double theta = kPi * latLong.y;
  const double r = std::min(std::floor(latLong.y * n), n - 1.0);
  const double theta0 = kPi * r / n, theta1 = kPi * (r + 1.0) / n;
  const double rowDelta = cosDifference(theta0, theta1);
  jacobian = 2.0 * kPi * n * rowDelta;
  const double f = cosDifference(theta0, theta) / rowDelta;  // (cos(theta0) - cos(theta)) / delta
  return {latLong.x, (r + std::clamp(f, 0.0, 1.0)) / n};
}

EnvOtSamplerMaps envOtSamplerMaps(const EnvImage& image) {
  EnvOtMaps maps = solveEnvOtMaps(image);
  return envOtSamplerMaps(std::move(maps.sun), maps.map);
}

EnvOtSamplerMaps envOtSamplerMaps(OtSunSplit sun, const OtMap& map) {
  QuadGridMap forward = forwardMap(map);
  QuadGridMap inverse = tabulatedInverse(forward, map.n);
  return {std::move(sun), map.n, std::move(forward), std::move(inverse)};
}

double envOtFwdPdf(const EnvOtSamplerMaps& maps, glm::dvec3 w) {
  double solidAngle = 0.0;
  const glm::dvec2 x = otDirectionToParameter(w, maps.densityGrid, solidAngle);
  const double jacobian = maps.forward.apply(x).jacobian;
  return mixture(maps.sun, w, jacobian > 0.0 && solidAngle > 0.0 ? jacobian / solidAngle : 0.0);
}

double envOtInvPdf(const EnvOtSamplerMaps& maps, glm::dvec3 w) {
  double solidAngle = 0.0;
  const glm::dvec2 x = otDirectionToParameter(w, maps.densityGrid, solidAngle);
  const auto otPart = [&]() -> double {
    if (!(solidAngle > 0.0)) return 0.0;
    // otInversePdf: G's cell around F(x) and its 8 neighbours first, then point location over G's image.
    const int m = maps.inverse.size();
    const glm::dvec2 guess = glm::clamp(maps.forward.apply(x).p, 0.0, 1.0) * double(m);
    const int gi = std::min(int(guess.x), m - 1), gj = std::min(int(guess.y), m - 1);
    constexpr int kAround[9][2] = {{0, 0},   {-1, 0}, {1, 0},  {0, -1}, {0, 1},
                                   {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
    for (const auto& offset : kAround) {
      const int i = gi + offset[0], j = gj + offset[1];
      if (i < 0 || j < 0 || i >= m || j >= m) continue;
      double jacobian = 0.0;
      if (invertInCell(maps.inverse, std::size_t(j) * std::size_t(m) + std::size_t(i), x, 1e-5, jacobian))
        return jacobian > 0.0 ? 1.0 / (jacobian * solidAngle) : 0.0;
    }
    const auto located = maps.inverse.invert(x);
    return located && located->jacobian > 0.0 ? 1.0 / (located->jacobian * solidAngle) : 0.0;
  };
  return mixture(maps.sun, w, otPart());
}

double nonConvexShare(const QuadGridMap& map) {
  const auto pieces = map.pieces();
  const auto split = std::count_if(pieces.begin(), pieces.end(),
                                   [](QuadPiece piece) { return piece != QuadPiece::Bilinear; });
  return pieces.empty() ? 0.0 : double(split) / double(pieces.size());
}

MapRoundTrip inverseRoundTrip(const QuadGridMap& forward, const QuadGridMap& inverse, int points) {
  return measureRoundTrip(
      points, [&](glm::dvec2 u) -> std::optional<glm::dvec2> { return forward.apply(inverse.apply(u).p).p; });
}

MapRoundTrip forwardRoundTrip(const QuadGridMap& forward, int points) {
  return measureRoundTrip(points, [&](glm::dvec2 u) -> std::optional<glm::dvec2> {
    const auto x = forward.invert(u);
    if (!x) return std::nullopt;
    return forward.apply(x->p).p;
  });
}

}  // namespace iblx
