// The OT solver's step lengths (line_search.h): the quartic merit's exact minimiser within the fold
// guard, the predictor's area bound and the curved step's search.
#include "engine/ot/line_search.h"

#include "engine/ot/geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace iblx {

namespace {

using Vec2 = glm::dvec2;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Smallest t > 0 with c0 + c1 t + c2 t^2 = 0, for c0 > 0 (infinity if the quadratic stays positive).
double firstPositiveRoot(double c0, double c1, double c2) {
  if (c2 == 0.0) return c1 < 0.0 ? -c0 / c1 : kInf;
  const double disc = c1 * c1 - 4.0 * c2 * c0;
  if (disc < 0.0) return kInf;
  const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));  // stable roots q/c2 and c0/q
  double best = kInf;
  for (double r : {q / c2, q != 0.0 ? c0 / q : kInf})
    if (r > 0.0) best = std::min(best, r);
  return best;
}

// Quartic E(t) = sum_k e[k] t^k and its derivative.
struct Quartic {
  std::array<double, 5> e{};
  double value(double t) const { return (((e[4] * t + e[3]) * t + e[2]) * t + e[1]) * t + e[0]; }
  double slope(double t) const { return ((4.0 * e[4] * t + 3.0 * e[3]) * t + 2.0 * e[2]) * t + e[1]; }
};

// argmin of E on [lo, hi] (lo <= 0 <= hi): E'' (a quadratic) splits the interval into pieces where E' is
// monotone; each sign change of E' is bisected. Exact up to rounding, with no cubic formula and no
// companion-matrix eigenvalues (which the line search of Nader & Guennebaud 2018 uses).
double minimiseQuartic(const Quartic& q, double lo, double hi) {
  std::vector<double> cuts{lo, hi};
  const double a = 12.0 * q.e[4], b = 6.0 * q.e[3], c = 2.0 * q.e[2];
  if (a != 0.0) {
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      const double s = -0.5 * (b + std::copysign(std::sqrt(disc), b));
      cuts.push_back(s / a);
      if (s != 0.0) cuts.push_back(c / s);
    }
  } else if (b != 0.0) {
    cuts.push_back(-c / b);
  }
  std::erase_if(cuts, [&](double t) { return !(t >= lo && t <= hi); });
  std::sort(cuts.begin(), cuts.end());
  double bestT = 0.0, bestE = q.value(0.0);
  const auto consider = [&](double t) {
    const double v = q.value(t);
    if (v < bestE) bestE = v, bestT = t;
  };
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    consider(cuts[i]);
    if (i + 1 == cuts.size()) break;
    double l = cuts[i], r = cuts[i + 1];
    double sl = q.slope(l);
    if ((sl > 0.0) == (q.slope(r) > 0.0)) continue;
    for (int it = 0; it < 100 && r - l > 1e-15 * std::max(1.0, std::abs(l)); ++it) {
      const double m = 0.5 * (l + r), sm = q.slope(m);
      if ((sm > 0.0) == (sl > 0.0))
        l = m, sl = sm;
      else
        r = m;
    }
    consider(0.5 * (l + r));
  }
  return bestT;
}

}  // namespace

OtLineStep otLineSearch(const OtGrid& grid, const OtMapState& map, std::span<const Vec2> motion,
                        const OtSolverOptions& options) {
  const int n = grid.n();
  const OtFoldGuard guard = options.foldGuard;
  const bool relative = options.relativeResidual;
  const std::span<const Vec2> pos = map.positions;
  // e0..e4, then the positive and negative step bounds (as maxima of -t).
  const auto sums = otReduceChunks<7>(
      grid.threads(), n, 8,
      [&](int lo, int hi) {
        std::array<double, 7> acc{0, 0, 0, 0, 0, -kInf, -kInf};
        double tPos = kInf, tNeg = kInf;
        for (int j = lo; j < hi; ++j)
          for (int i = 0; i < n; ++i) {
            const auto [p00, p10, p11, p01] = grid.quad(i, j);
            const std::size_t c = grid.cell(i, j);
            const Vec2 d1 = pos[p11] - pos[p00], d2 = pos[p01] - pos[p10];
            const Vec2 e1 = motion[p11] - motion[p00], e2 = motion[p01] - motion[p10];
            double b = 0.5 * (cross2(d1, e2) + cross2(e1, d2)), a = 0.5 * cross2(e1, e2);
            double r = map.residual[c];
            if (relative) {
              const double w = 1.0 / map.mass[c];
              b *= w, a *= w, r *= w;
            }
            acc[0] += r * r, acc[1] += 2.0 * r * b, acc[2] += b * b + 2.0 * a * r, acc[3] += 2.0 * a * b;
            acc[4] += a * a;
            if (guard == OtFoldGuard::Area) {
              const double area = map.residual[c] + map.mass[c];
              if (relative) b *= map.mass[c], a *= map.mass[c];
              if (area > 0.0) {
                tPos = std::min(tPos, firstPositiveRoot(area, b, a));
                tNeg = std::min(tNeg, firstPositiveRoot(area, -b, a));
              }
              continue;
            }
            if (guard == OtFoldGuard::None) continue;
            // Convex: every corner's cross product (P_next - P) x (P_prev - P), also quadratic in t, stays
            // positive. Corners counter-clockwise: 00, 10, 11, 01.
            const std::array<std::size_t, 4> ring{p00, p10, p11, p01};
            for (int k = 0; k < 4; ++k) {
              const std::size_t pc = ring[std::size_t(k)], pn = ring[std::size_t((k + 1) & 3)],
                                pp = ring[std::size_t((k + 3) & 3)];
              const Vec2 u = pos[pn] - pos[pc], du = motion[pn] - motion[pc];
              const Vec2 w = pos[pp] - pos[pc], dw = motion[pp] - motion[pc];
              const double c0 = cross2(u, w);
              if (!(c0 > 0.0)) continue;  // already degenerate: not a constraint
              const double c1 = cross2(u, dw) + cross2(du, w), c2 = cross2(du, dw);
              tPos = std::min(tPos, firstPositiveRoot(c0, c1, c2));
              tNeg = std::min(tNeg, firstPositiveRoot(c0, -c1, c2));
            }
          }
        acc[5] = -tPos, acc[6] = -tNeg;
        return acc;
      },
      {false, false, false, false, false, true, true});
  Quartic q;
  for (int k = 0; k < 5; ++k) q.e[std::size_t(k)] = sums[std::size_t(k)];
  constexpr double kMaxStep = 10.0;  // as Nader & Guennebaud 2018's released solver (github.com/ggael/otmap)
  const double hi = std::min(kMaxStep, options.boundaryFraction * -sums[5]);
  const double lo = -std::min(kMaxStep, options.boundaryFraction * -sums[6]);
  const double t = minimiseQuartic(q, lo, hi);
  OtLineStep step;
  step.guardLimited = hi < kMaxStep && t >= hi * (1.0 - 1e-12);
  // Require a real decrease, not one lost in rounding.
  if (q.value(t) < q.e[0] * (1.0 - 1e-12)) step.t = t;
  return step;
}

double otAreaStepBound(const OtGrid& grid, std::span<const Vec2> positions, std::span<const Vec2> motion) {
  const int n = grid.n();
  return -otReduceChunks<1>(
      grid.threads(), n, 8,
      [&](int lo, int hi) {
        double t = kInf;
        for (int j = lo; j < hi; ++j)
          for (int i = 0; i < n; ++i) {
            const auto [p00, p10, p11, p01] = grid.quad(i, j);
            const Vec2 d1 = positions[p11] - positions[p00], d2 = positions[p01] - positions[p10];
            const Vec2 e1 = motion[p11] - motion[p00], e2 = motion[p01] - motion[p10];
            t = std::min(t, firstPositiveRoot(0.5 * cross2(d1, d2), 0.5 * (cross2(d1, e2) + cross2(e1, d2)),
                                              0.5 * cross2(e1, e2)));
          }
        return std::array<double, 1>{-t};
      },
      {true})[0];
}

void otQuadraticAreaTerms(const OtGrid& grid, std::span<const Vec2> motion, std::span<double> a) {
  const int n = grid.n();
  parallelChunks(grid.threads(), n, 8, [&](int lo, int hi) {
    for (int j = lo; j < hi; ++j)
      for (int i = 0; i < n; ++i) {
        const auto [p00, p10, p11, p01] = grid.quad(i, j);
        a[grid.cell(i, j)] = 0.5 * cross2(motion[p11] - motion[p00], motion[p01] - motion[p10]);
      }
  });
}

double otCurvedStepLength(const OtGrid& grid, const OtMapState& map, std::span<const Vec2> motion,
                          std::span<const Vec2> curveMotion, double t, bool relativeResidual) {
  const int n = grid.n();
  const std::span<const Vec2> pos = map.positions;
  // The merit and the number of quads that would come too close to degenerate, at P + t1 G + t2 G2.
  const auto evaluate = [&](double t1, double t2) {
    return otReduceChunks<2>(grid.threads(), n, 8, [&](int lo, int hi) {
      std::array<double, 2> acc{0.0, 0.0};
      for (int j = lo; j < hi; ++j)
        for (int i = 0; i < n; ++i) {
          const auto [p00, p10, p11, p01] = grid.quad(i, j);
          const auto at = [&](std::size_t p) { return pos[p] + t1 * motion[p] + t2 * curveMotion[p]; };
          const double area = 0.5 * cross2(at(p11) - at(p00), at(p01) - at(p10));
          const std::size_t c = grid.cell(i, j);
          if (map.residual[c] + map.mass[c] > 0.0 && !(area > 1e-3 * map.mass[c])) acc[1] += 1.0;
          const double r = (area - map.mass[c]) / (relativeResidual ? map.mass[c] : 1.0);
          acc[0] += r * r;
        }
      return acc;
    });
  };
  const double straight = evaluate(t, 0.0)[0];
  for (double tau = 1.0; tau > t; tau *= 0.8) {
    const auto [merit, degenerate] = evaluate(tau, tau * tau);
    if (degenerate == 0.0 && merit < straight) return tau;
  }
  return 0.0;
}

}  // namespace iblx
