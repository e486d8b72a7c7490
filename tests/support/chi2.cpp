// Chi-square harness: adaptive cell integration of the pdf, histogram, pooling, p-value and failure dumps.
#include "tests/support/chi2.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <utility>

namespace iblx::test {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Direction on the unit sphere at (phi, z = cos(theta)) of the equal-area domain (y up, phi from +X to +Z).
glm::dvec3 domainToDirection(double phi, double z) {
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), z, r * std::sin(phi)};
}

// Sub-cells of one refinement level: a global grid of nx x ny quads, each of solid angle `area`.
struct LevelGrid {
  int64_t nx = 0, ny = 0, perCellX = 0, perCellY = 0;
  double dPhi = 0.0, dZ = 0.0, area = 0.0;
  glm::dvec3 midpoint(int64_t x, int64_t y) const {
    return domainToDirection((x + 0.5) * dPhi, -1.0 + (y + 0.5) * dZ);
  }
};

std::string fileSafe(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out.empty() ? std::string("chi2") : out;
}

// Writes both tables (rows from cos(theta) = 1 down to -1, columns along phi) and returns the file's path.
std::string dumpTables(const Chi2Options& o, const std::vector<double>& expected,
                       const std::vector<double>& observed, const std::string& summary) {
  std::error_code ec;
  std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
  if (ec) dir = ".";
  const std::filesystem::path path = dir / ("iblx_chi2_" + fileSafe(o.label) + ".txt");
  std::ofstream out(path);
  out << "# " << summary << "\n# cells: " << o.phiCells << " (phi in [0,2pi), columns) x " << o.cosThetaCells
      << " (cos(theta) from 1 down to -1, rows)\n";
  const auto table = [&](const char* name, const std::vector<double>& t) {
    out << "\n# " << name << "\n";
    for (int j = o.cosThetaCells - 1; j >= 0; --j) {
      for (int i = 0; i < o.phiCells; ++i) out << (i ? " " : "") << t[std::size_t(j) * o.phiCells + i];
      out << "\n";
    }
  };
  out.precision(6);
  table("expected", expected);
  table("observed", observed);
  return path.string();
}

// splitmix64 (Steele, Lea, Flood 2014): one 64-bit state, well-mixed outputs.
std::uint64_t splitMix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

}  // namespace

std::vector<glm::dvec2> uniformPoints(std::size_t count, std::uint64_t seed) {
  std::vector<glm::dvec2> points(count);
  std::uint64_t state = seed;
  for (auto& p : points) {
    p.x = double(splitMix64(state) >> 11) * 0x1p-53;
    p.y = double(splitMix64(state) >> 11) * 0x1p-53;
  }
  return points;
}

namespace {

// Both regularised incomplete gammas {P, Q}; the one computed directly keeps full relative precision.
std::pair<double, double> regularizedGamma(double a, double x) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!(a > 0.0) || !(x >= 0.0)) return {kNaN, kNaN};
  if (x == 0.0) return {0.0, 1.0};
  constexpr double kEps = 1e-15, kTiny = 1e-300;
  constexpr int kMaxIterations = 10000;
  // Prefactor x^a e^-x / Gamma(a), in logs to avoid overflow.
  const double prefactor = std::exp(a * std::log(x) - x - std::lgamma(a));
  if (x < a + 1.0) {
    // P(a, x) = prefactor * sum_n x^n / (a (a+1) ... (a+n)).
    double ap = a, term = 1.0 / a, sum = term;
    for (int n = 0; n < kMaxIterations && std::abs(term) > std::abs(sum) * kEps; ++n) {
      ap += 1.0;
      term *= x / ap;
      sum += term;
    }
    const double p = std::clamp(sum * prefactor, 0.0, 1.0);
    return {p, 1.0 - p};
  }
  // Q(a, x) = prefactor * 1/(x+1-a- 1(1-a)/(x+3-a- 2(2-a)/(x+5-a- ...))), by the modified Lentz method.
  double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxIterations; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEps) break;
  }
  const double q = std::clamp(prefactor * h, 0.0, 1.0);
  return {1.0 - q, q};
}

}  // namespace

double regularizedGammaP(double a, double x) {
  return regularizedGamma(a, x).first;
}
double regularizedGammaQ(double a, double x) {
  return regularizedGamma(a, x).second;
}

double chi2PValue(double statistic, int degreesOfFreedom) {
  if (degreesOfFreedom < 1) return std::numeric_limits<double>::quiet_NaN();
  return regularizedGammaQ(0.5 * degreesOfFreedom, 0.5 * std::max(statistic, 0.0));
}

Chi2Result chi2Test(std::span<const glm::dvec3> samples, const BatchPdf& pdf, const Chi2Options& o) {
  Chi2Result result;
  const int64_t cellCount = int64_t(o.phiCells) * o.cosThetaCells;
  if (o.phiCells < 1 || o.cosThetaCells < 1 || o.ires < 1 || samples.empty()) {
    result.message = o.label + ": invalid options or no samples";
    return result;
  }
  const double n = double(samples.size());

  // Histogram of the samples over the (phi, cos(theta)) cells.
  std::vector<double> observed(std::size_t(cellCount), 0.0);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const glm::dvec3 w = samples[k];
    const double len = glm::length(w);
    if (!std::isfinite(len) || len == 0.0) {
      result.message = o.label + ": sample " + std::to_string(k) + " is not a finite non-zero direction";
      return result;
    }
    double phi = std::atan2(w.z, w.x);
    if (phi < 0.0) phi += kTwoPi;
    const int i = std::clamp(int(phi / kTwoPi * o.phiCells), 0, o.phiCells - 1);
    const int j = std::clamp(int((w.y / len + 1.0) * 0.5 * o.cosThetaCells), 0, o.cosThetaCells - 1);
    observed[std::size_t(j) * o.phiCells + i] += 1.0;
  }

  // Integral of the pdf over each cell: midpoint rule on ires x ires sub-cells, refined 2x2 where the pdf
  // jumps between neighbouring sub-cells by more than refineTolerance expected samples (the midpoint rule is
  // exact on a constant pdf, so only quads cut by a discontinuity need a finer rule).
  std::vector<double> cellIntegral(std::size_t(cellCount), 0.0);
  LevelGrid g;
  g.perCellX = o.ires;
  g.perCellY = o.ires;
  g.nx = int64_t(o.phiCells) * o.ires;
  g.ny = int64_t(o.cosThetaCells) * o.ires;
  g.dPhi = kTwoPi / double(g.nx);
  g.dZ = 2.0 / double(g.ny);
  g.area = g.dPhi * g.dZ;
  std::vector<int64_t> keys(std::size_t(g.nx * g.ny));
  std::iota(keys.begin(), keys.end(), int64_t(0));  // key = y * nx + x at the current level
  for (int depth = 0;; ++depth) {
    std::vector<glm::dvec3> points(keys.size());
    for (std::size_t k = 0; k < keys.size(); ++k) points[k] = g.midpoint(keys[k] % g.nx, keys[k] / g.nx);
    const std::vector<double> values = pdf(points);
    if (values.size() != points.size()) {
      result.message = o.label + ": the pdf function returned " + std::to_string(values.size()) +
                       " values for " + std::to_string(points.size()) + " directions";
      return result;
    }
    std::unordered_map<int64_t, std::size_t> index;
    index.reserve(keys.size() * 2);
    for (std::size_t k = 0; k < keys.size(); ++k) {
      if (!std::isfinite(values[k]) || values[k] < 0.0) {
        result.message = o.label + ": pdf is " + std::to_string(values[k]) +
                         " (negative or not finite) at (" + std::to_string(points[k].x) + ", " +
                         std::to_string(points[k].y) + ", " + std::to_string(points[k].z) + ")";
        return result;
      }
      index.emplace(keys[k], k);
    }
    // Flag both quads of every neighbouring pair (phi wraps around) whose difference matters.
    std::vector<char> refine(keys.size(), 0);
    if (depth < o.maxRefineDepth) {
      // An edge crossing a cell cuts perCell quads, all with the same offset from their midpoints, so their
      // errors add up: compare the jump over that whole strip of quads with the tolerance.
      const double strip = g.area * double(std::max(g.perCellX, g.perCellY));
      const double threshold = o.refineTolerance / (n * strip);
      for (std::size_t k = 0; k < keys.size(); ++k) {
        const int64_t x = keys[k] % g.nx, y = keys[k] / g.nx;
        const auto compare = [&](int64_t neighbour) {
          const auto it = index.find(neighbour);
          if (it != index.end() && std::abs(values[k] - values[it->second]) > threshold)
            refine[k] = refine[it->second] = 1;
        };
        // 8-neighbourhood (4 directions plus symmetry): a quad cut by a corner of a feature has no edge
        // neighbour that differs from it, only a diagonal one.
        if (g.nx > 1) compare(y * g.nx + (x + 1) % g.nx);
        if (y + 1 < g.ny) {
          compare((y + 1) * g.nx + x);
          if (g.nx > 1) {
            compare((y + 1) * g.nx + (x + 1) % g.nx);
            compare((y + 1) * g.nx + (x + g.nx - 1) % g.nx);
          }
        }
      }
    }
    // Accumulate the quads that stay, split the others.
    std::vector<int64_t> next;
    for (std::size_t k = 0; k < keys.size(); ++k) {
      const int64_t x = keys[k] % g.nx, y = keys[k] / g.nx;
      if (!refine[k]) {
        cellIntegral[std::size_t((y / g.perCellY) * o.phiCells + x / g.perCellX)] += values[k] * g.area;
        continue;
      }
      for (int64_t j = 0; j < 2; ++j)
        for (int64_t i = 0; i < 2; ++i) next.push_back((2 * y + j) * (2 * g.nx) + 2 * x + i);
    }
    if (next.empty()) break;
    g.nx *= 2, g.ny *= 2, g.perCellX *= 2, g.perCellY *= 2;
    g.dPhi *= 0.5, g.dZ *= 0.5, g.area *= 0.25;
    keys = std::move(next);
  }
  result.pdfIntegral = std::accumulate(cellIntegral.begin(), cellIntegral.end(), 0.0);

  // Expected counts; a sample in a cell that expects none is an outright failure.
  std::vector<double> expected(cellIntegral.size());
  for (std::size_t c = 0; c < expected.size(); ++c) expected[c] = n * cellIntegral[c];
  const double zeroExpected = 1e-12 * n;
  std::ostringstream why;
  for (std::size_t c = 0; c < expected.size(); ++c) {
    if (expected[c] < zeroExpected && observed[c] > 0.0) {
      why << observed[c] << " sample(s) in cell (phi " << c % o.phiCells << ", cos(theta) " << c / o.phiCells
          << ") whose expected count is " << expected[c] << "; ";
    }
  }

  // Chi-square over cells sorted by expected count; cells below minExpected are pooled (and the pool keeps
  // absorbing cells until it reaches minExpected itself).
  std::vector<std::size_t> order(expected.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
  double statistic = 0.0, pooledExpected = 0.0, pooledObserved = 0.0;
  int terms = 0;
  for (std::size_t c : order) {
    if (expected[c] < zeroExpected) continue;  // empty cells: checked above
    if (expected[c] < o.minExpected || (pooledExpected > 0.0 && pooledExpected < o.minExpected)) {
      pooledExpected += expected[c];
      pooledObserved += observed[c];
      continue;
    }
    const double d = observed[c] - expected[c];
    statistic += d * d / expected[c];
    ++terms;
  }
  if (pooledExpected > 0.0) {
    const double d = pooledObserved - pooledExpected;
    statistic += d * d / pooledExpected;
    ++terms;
  }
  // One constraint: the counts sum to N.
  result.degreesOfFreedom = terms - 1;
  result.statistic = statistic;
  const double alpha = 1.0 - std::pow(1.0 - o.significance, 1.0 / std::max(o.testCount, 1));
  std::ostringstream summary;
  summary << o.label << ": chi2 = " << statistic << ", dof = " << result.degreesOfFreedom;
  if (result.degreesOfFreedom < 1) {
    why << "fewer than two cells expect " << o.minExpected << " samples; use more samples or fewer cells; ";
  } else {
    result.pValue = chi2PValue(statistic, result.degreesOfFreedom);
    summary << ", p = " << result.pValue << " (Sidak-adjusted significance " << alpha << ")";
    if (!(result.pValue >= alpha)) why << "p-value below the significance level; ";
  }
  summary << ", pdf integral = " << result.pdfIntegral << ", N = " << samples.size();
  result.passed = why.str().empty();
  result.message = summary.str();
  if (!result.passed)
    result.message +=
        "; FAILED: " + why.str() + "tables in " + dumpTables(o, expected, observed, summary.str());
  return result;
}

}  // namespace iblx::test
