// Tests of the OT map solver (engine/ot/solver.h) and its parts: the DCT (engine/ot/dct.h) against its
// definition, GMRES (engine/ot/gmres.h) on small nonsymmetric systems, the Newton system's Jacobian
// (engine/ot/newton.h) against the exact area change, the coarse-to-fine transfers (engine/ot/multilevel.h);
// the identity map, mass residuals and folds on smooth, sun and half-zero densities, boundary vertices, the
// density of a lat-long environment against the analytic sin(theta) integral, bad input.
#include "engine/ot/solver.h"

#include "engine/core/error.h"
#include "engine/ot/dct.h"
#include "engine/ot/gmres.h"
#include "engine/ot/grid.h"
#include "engine/ot/multilevel.h"
#include "engine/ot/newton.h"
#include "tests/support/hard_envs.h"

#include "tests/support/ot_densities.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace iblx;
using namespace iblx::test;

namespace {

constexpr double kPiD = std::numbers::pi;

// The solver's own guarantees, checked from the returned vertices alone.
void checkMap(const OtMap& map, const OtSolverOptions& options) {
  const int n = map.n;
  REQUIRE(map.vertices.size() == std::size_t(n + 1) * (n + 1));
  CHECK(map.converged);
  CHECK(map.l2 <= options.targetL2);
  CHECK(map.l1 <= options.targetL1);
  CHECK(map.l2 <= 1e-7);  // the solver's required tolerances, whatever the defaults become
  CHECK(map.l1 <= 1e-3);
  // Recompute the residuals independently of the solver's bookkeeping.
  const std::vector<double> areas = otQuadAreas(map.vertices, n);
  double l1 = 0.0, total = 0.0;
  int negative = 0;
  for (std::size_t c = 0; c < areas.size(); ++c) {
    l1 += std::abs(areas[c] - map.density[c] / (double(n) * n));
    total += areas[c];
    negative += areas[c] <= 0.0 ? 1 : 0;
  }
  CHECK(l1 == doctest::Approx(map.l1).epsilon(1e-9));
  CHECK(total == doctest::Approx(1.0).epsilon(1e-12));  // the square maps onto itself
  CHECK(negative == 0);
  CHECK(map.negativeAreaQuads == 0);
  // Boundary vertices slide along their side; corners stay put.
  for (int k = 0; k <= n; ++k) {
    const auto at = [&](int i, int j) { return map.vertices[std::size_t(j) * (n + 1) + i]; };
    CHECK(at(0, k).x == 0.0);
    CHECK(at(n, k).x == doctest::Approx(1.0).epsilon(1e-15));
    CHECK(at(k, 0).y == 0.0);
    CHECK(at(k, n).y == doctest::Approx(1.0).epsilon(1e-15));
    for (const glm::dvec2 p : {at(0, k), at(n, k), at(k, 0), at(k, n)}) {
      CHECK(p.x >= 0.0);
      CHECK(p.x <= 1.0 + 1e-15);
      CHECK(p.y >= 0.0);
      CHECK(p.y <= 1.0 + 1e-15);
    }
  }
  CHECK(map.vertices.front() == glm::dvec2(0.0, 0.0));
  MESSAGE("n = " << n << ": " << map.iterations << " iterations (+" << map.coarseIterations << " coarse), "
                 << map.seconds << " s, L2 " << map.l2 << ", L1 " << map.l1 << ", Linf " << map.linf
                 << ", non-convex quads " << map.foldedQuads);
}

// A dense row-major n x n matrix as a GMRES operator: out = A in.
Gmres::LinearMap denseMap(const std::vector<double>& a, int n) {
  return [&a, n](std::span<const double> in, std::span<double> out) {
    for (int r = 0; r < n; ++r) {
      double s = 0.0;
      for (int c = 0; c < n; ++c) s += a[std::size_t(r) * n + c] * in[std::size_t(c)];
      out[std::size_t(r)] = s;
    }
  };
}

// The convection-diffusion matrix tridiag(-1 - p, 2 + shift, -1 + p): nonsymmetric for p != 0, and
// nonnormal, so GMRES needs many steps without a preconditioner.
std::vector<double> convectionDiffusion(int n, double p, double shift) {
  std::vector<double> a(std::size_t(n) * n, 0.0);
  for (int r = 0; r < n; ++r) {
    a[std::size_t(r) * n + r] = 2.0 + shift;
    if (r > 0) a[std::size_t(r) * n + r - 1] = -1.0 - p;
    if (r + 1 < n) a[std::size_t(r) * n + r + 1] = -1.0 + p;
  }
  return a;
}

// ||W (b - A x)|| / ||W b||, computed directly.
double weightedRelativeResidual(const std::vector<double>& a, int n, std::span<const double> x,
                                std::span<const double> b, std::span<const double> w) {
  std::vector<double> ax(static_cast<std::size_t>(n));
  denseMap(a, n)(x, ax);
  double r2 = 0.0, b2 = 0.0;
  for (std::size_t i = 0; i < std::size_t(n); ++i) {
    r2 += (w[i] * (b[i] - ax[i])) * (w[i] * (b[i] - ax[i]));
    b2 += (w[i] * b[i]) * (w[i] * b[i]);
  }
  return std::sqrt(r2 / b2);
}

// density times e^u per cell, u uniform in [-amplitude, amplitude] (fixed seed): a real map's detail.
std::vector<double> textured(std::vector<double> density, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> texture(-amplitude, amplitude);
  for (double& v : density) v *= std::exp(texture(rng));
  return density;
}

}  // namespace

TEST_CASE("OT DCT: forward rows match the definition and inverse rows undo them") {
  for (int n : {1, 2, 6, 8, 16, 12}) {
    CAPTURE(n);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    std::vector<double> a(std::size_t(n) * n);
    for (double& v : a) v = uni(rng);
    const std::vector<double> original = a;
    const DctPlan plan(n);
    plan.forwardRows(a, 2);
    for (int r = 0; r < n; ++r)
      for (int k = 0; k < n; ++k) {
        double expected = 0.0;
        for (int i = 0; i < n; ++i)
          expected += original[std::size_t(r) * n + i] * std::cos(kPiD * k * (2 * i + 1) / (2.0 * n));
        CHECK(a[std::size_t(r) * n + k] == doctest::Approx(expected).epsilon(1e-12).scale(1.0));
      }
    plan.inverseRows(a, 1);
    for (std::size_t c = 0; c < a.size(); ++c)
      CHECK(a[c] == doctest::Approx(original[c]).epsilon(1e-12).scale(1.0));
    transposeSquare(a, n);
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c)
        CHECK(a[std::size_t(r) * n + c] ==
              doctest::Approx(original[std::size_t(c) * n + r]).epsilon(1e-12).scale(1.0));
  }
}

TEST_CASE("OT solver: a uniform density gives the identity map in 0 iterations") {
  for (int n : {16, 64}) {
    const std::vector<double> uniform(std::size_t(n) * n, 3.0);  // any scale: normalised to mean 1
    const OtMap map = solveOtMap(uniform, n);
    CHECK(map.iterations == 0);
    CHECK(map.converged);
    CHECK(map.l2 < 1e-28);
    CHECK(map.foldedQuads == 0);
    CHECK(map.negativeAreaQuads == 0);
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const glm::dvec2 p = map.vertices[std::size_t(j) * (n + 1) + i];
        CHECK(p.x == doctest::Approx(double(i) / n).epsilon(1e-14).scale(1.0));
        CHECK(p.y == doctest::Approx(double(j) / n).epsilon(1e-14).scale(1.0));
      }
  }
}

TEST_CASE("OT solver: smooth density, n = 64 and 128") {
  const OtSolverOptions options;
  for (int n : {64, 128}) {
    const OtMap map = solveOtMap(smoothDensity(n), n, options);
    checkMap(map, options);
    CHECK(map.foldedQuads == 0);  // a smooth density keeps every quad strictly convex
  }
}

TEST_CASE("OT solver: half-zero density (floored), n = 64 and 128") {
  const OtSolverOptions options;
  for (int n : {64, 128}) {
    const OtMap map = solveOtMap(halfZeroDensity(n), n, options);
    checkMap(map, options);
    CHECK(map.foldedQuads == 0);
    // The floor: zero cells target eps * mean before renormalisation.
    // Mean 0.5, floor eps * 0.5, floored mean 0.5 (1 + eps / 2) -> mean-1 floor eps / (1 + eps / 2).
    CHECK(map.density[0] == doctest::Approx(options.floorFraction / (1.0 + 0.5 * options.floorFraction)));
  }
}

TEST_CASE("OT solver: sun 1e3 over a few cells, n = 64 and 128") {
  const OtSolverOptions options;
  for (int n : {64, 128}) {
    const OtMap map = solveOtMap(sunDensity(n, 1e3), n, options);
    checkMap(map, options);
    // Known limit: the slivers around the sun converge with positive areas but some are not convex.
    WARN(map.foldedQuads == 0);
  }
}

// Issue 4's hard case: a sun 1e5 times the sky over a Gaussian of sigma = 1 cell
// (tools/bench/ot_solver_bench.cpp `sun1e5`): 99% of the mass in a few cells. Converged with no negative-area
// quad; some slivers around the sun are not convex (the quad grid map splits those into two triangles).
TEST_CASE("OT solver: sun 1e5 over a few cells, n = 64 and 128") {
  const OtSolverOptions options;
  for (int n : {64, 128}) {
    const OtMap map = solveOtMap(sunDensity(n, 1e5), n, options);
    checkMap(map, options);
  }
}

// Regression: the coarse potential carries the checkerboard mode the 2x2 gradient stencil cannot see, and
// prolonged by plain bilinear interpolation of cell values it folded 30-45 % of the fine quads of every real
// map, so every level silently restarted from the identity (with that prolongation, levels 64 and 128
// restart here). A textured density (a sky times a per-cell factor in [e^-2, e^2], like a real map's detail)
// must start every level from its coarse solution, with at most 0.1 % of its quads folded. (Not checkMap: on
// this density two side vertices slide past a corner by up to 5e-4, a known limit of the boundary rule, see
// docs/ot_solver.md.)
TEST_CASE("OT solver: every level starts from the prolonged coarse map (textured density, n = 128)") {
  constexpr int n = 128;
  const OtMap map = solveOtMap(textured(smoothDensity(n), 2.0, 7), n);
  CHECK(map.converged);
  CHECK(map.negativeAreaQuads == 0);
  REQUIRE(map.levels.size() == 4);  // 16, 32, 64, 128
  for (const OtLevelStats& level : map.levels) {
    CAPTURE(level.n);
    CHECK(level.startFoldedQuads <= level.n * level.n / 1000);  // a few next to the texture's extremes
    CHECK(level.restartScale == 0.0);
  }
  CHECK(map.levels.back().n == n);
}

// Regression: a stage clipped at s = 1 that failed was retried with half its nominal step, which from reached
// = 0.8125 with step 0.5 is again s = 1: the same stage from the same map, repeated exactly.
TEST_CASE("OT solver: a failed continuation stage is retried with a smaller step than the one it attempted") {
  const OtSolverOptions options;
  const double reached = 0.8125, next = std::min(1.0, reached + 0.5);
  const double halved = otRetriedStageStep(reached, next, 0.6, false, options);
  CHECK(halved == doctest::Approx(0.5 * (next - reached)));
  CHECK(reached + halved < 1.0);
  // Abandoned at a short first Newton step: scaled by firstStep / 0.5, within [1/16, 1/2].
  CHECK(otRetriedStageStep(0.0, 0.5, 0.1, true, options) == doctest::Approx(0.5 * 0.2));
  CHECK(otRetriedStageStep(0.0, 0.5, 0.001, true, options) == doctest::Approx(0.5 / 16.0));
  CHECK(otRetriedStageStep(0.0, 0.5, 0.24, true, options) == doctest::Approx(0.5 * 0.48));
  // Never below minStageStep.
  CHECK(otRetriedStageStep(0.5, 0.5 + 1e-4, 0.6, false, options) == options.minStageStep);
}

// The continuation's stage targets are a power mean of the start's areas and the target: the geometric (0),
// the default (1/2) and the arithmetic (1) path must all reach the target on a hard density, with no fold.
TEST_CASE("OT solver: every continuation path (homotopyPower 0, 1/2, 1) converges on a textured 10^5 sun") {
  constexpr int n = 64;
  for (const double power : {0.0, 0.5, 1.0}) {
    CAPTURE(power);
    OtSolverOptions options;
    options.homotopyPower = power;
    const OtMap map = solveOtMap(textured(sunDensity(n, 1e5), 3.0, 4), n, options);
    CHECK(map.converged);
    CHECK(map.negativeAreaQuads == 0);
    CHECK(map.l2 <= options.targetL2);
  }
  OtSolverOptions outside;
  outside.homotopyPower = 1.5;
  CHECK_THROWS_AS(solveOtMap(textured(sunDensity(n, 1e5), 3.0, 4), n, outside), Error);
}

// A 10^5 sun on a sky textured by e^+-3 per cell, at n = 128: its prolonged coarse maps fold quads next to
// the sun. Each such level must smooth psi until no quad folds and start there (not part of the way from the
// identity), and converge with no negative area; with maxSmoothingPasses = 0 it must start part of the way
// from the identity instead (not from the identity, not past a fold) and converge too.
TEST_CASE(
    "OT solver: a folded prolonged start is smoothed until it unfolds, else restarted part of the way") {
  constexpr int n = 128;
  const std::vector<double> density = textured(sunDensity(n, 1e5), 3.0, 4);
  for (const int maxPasses : {OtSolverOptions{}.maxSmoothingPasses, 0}) {
    CAPTURE(maxPasses);
    OtSolverOptions options;
    options.maxSmoothingPasses = maxPasses;
    const OtMap map = solveOtMap(density, n, options);
    CHECK(map.converged);
    CHECK(map.negativeAreaQuads == 0);
    int folded = 0;
    for (const OtLevelStats& level : map.levels) {
      CAPTURE(level.n);
      if (!level.foldedStart()) continue;
      ++folded;
      if (maxPasses > 0) {
        CHECK(level.smoothingPasses >= 1);
        CHECK(level.restartScale == 0.0);
      } else {
        CHECK(level.smoothingPasses == 0);
        CHECK(level.restartScale > 0.0);
        CHECK(level.restartScale < 1.0);  // the whole prolonged map folds, so only part of the way
      }
    }
    CHECK(folded >= 1);
  }
}

TEST_CASE("OT solver: the Convex guard never makes a quad non-convex (smooth density, coarse-to-fine off)") {
  OtSolverOptions options;
  options.foldGuard = OtFoldGuard::Convex;
  options.coarseToFine = false;
  const OtMap map = solveOtMap(smoothDensity(64), 64, options);
  checkMap(map, options);
  CHECK(map.foldedQuads == 0);
}

TEST_CASE("OT GMRES: solves a nonsymmetric system to the tolerance, and the solution is the system's") {
  constexpr int n = 40;
  const std::vector<double> a = convectionDiffusion(n, 0.6, 0.05);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<double> expected(static_cast<std::size_t>(n)), b(expected.size()), x(expected.size(), 7.0);
  for (double& v : expected) v = uni(rng);
  denseMap(a, n)(expected, b);
  const std::vector<double> ones(static_cast<std::size_t>(n), 1.0);
  const Gmres::LinearMap identity = [](std::span<const double> in, std::span<double> out) {
    std::copy(in.begin(), in.end(), out.begin());
  };
  Gmres gmres;
  const Gmres::Result result = gmres.solve(denseMap(a, n), identity, b, ones, n, 1e-12, x);
  CHECK(result.relativeResidual <= 1e-12);
  CHECK(result.steps >= 2);  // a nonsymmetric tridiagonal system is not solved in one step
  CHECK(result.steps <= n);  // in exact arithmetic at most n
  CHECK(weightedRelativeResidual(a, n, x, b, ones) <= 1e-10);
  for (std::size_t i = 0; i < expected.size(); ++i)
    CHECK(x[i] == doctest::Approx(expected[i]).epsilon(1e-8).scale(1.0));

  // A loose tolerance stops early, and the residual it reports is the true one (the Givens rotations' running
  // residual, not an estimate).
  const Gmres::Result loose = gmres.solve(denseMap(a, n), identity, b, ones, n, 0.1, x);
  CHECK(loose.steps < result.steps);
  CHECK(loose.relativeResidual <= 0.1);
  CHECK(weightedRelativeResidual(a, n, x, b, ones) == doctest::Approx(loose.relativeResidual).epsilon(1e-9));

  // A zero right-hand side gives x = 0 at no cost.
  const std::vector<double> zero(static_cast<std::size_t>(n), 0.0);
  const Gmres::Result none = gmres.solve(denseMap(a, n), identity, zero, ones, n, 0.1, x);
  CHECK(none.steps == 0);
  CHECK(none.relativeResidual == 0.0);
  CHECK(std::all_of(x.begin(), x.end(), [](double v) { return v == 0.0; }));
}

TEST_CASE("OT GMRES: row weights set the norm, and the preconditioner is applied on the right") {
  constexpr int n = 30;
  // Rows scaled over six orders of magnitude, as the OT Jacobian's rows are by the cells' masses.
  std::vector<double> a = convectionDiffusion(n, 0.3, 0.1), scale(static_cast<std::size_t>(n)),
                      weights(scale.size());
  for (int r = 0; r < n; ++r) {
    scale[std::size_t(r)] = std::pow(10.0, 6.0 * r / (n - 1));
    weights[std::size_t(r)] = 1.0 / scale[std::size_t(r)];
    for (int c = 0; c < n; ++c) a[std::size_t(r) * n + c] *= scale[std::size_t(r)];
  }
  std::vector<double> b(scale.size()), x(scale.size());
  for (int r = 0; r < n; ++r) b[std::size_t(r)] = scale[std::size_t(r)] * std::sin(0.3 * r + 1.0);
  Gmres gmres;
  // The reported residual is the weighted one, whether GMRES converged or was stopped.
  for (const int steps : {3, n}) {
    CAPTURE(steps);
    const Gmres::Result result = gmres.solve(
        denseMap(a, n),
        [](std::span<const double> in, std::span<double> out) {
          std::copy(in.begin(), in.end(), out.begin());
        },
        b, weights, steps, 1e-6, x);
    CHECK(result.steps <= steps);
    CHECK(weightedRelativeResidual(a, n, x, b, weights) ==
          doctest::Approx(result.relativeResidual).epsilon(1e-3));
  }
  // The exact inverse as the preconditioner: one step, whatever the system.
  std::vector<double> columns(std::size_t(n) * n);  // A^-1 by Gauss-Jordan on [A | I]
  {
    std::vector<double> m = a, inv(std::size_t(n) * n, 0.0);
    for (int r = 0; r < n; ++r) inv[std::size_t(r) * n + r] = 1.0;
    for (int k = 0; k < n; ++k) {
      int pivot = k;
      for (int r = k + 1; r < n; ++r)
        if (std::abs(m[std::size_t(r) * n + k]) > std::abs(m[std::size_t(pivot) * n + k])) pivot = r;
      for (int c = 0; c < n; ++c) {
        std::swap(m[std::size_t(k) * n + c], m[std::size_t(pivot) * n + c]);
        std::swap(inv[std::size_t(k) * n + c], inv[std::size_t(pivot) * n + c]);
      }
      const double d = m[std::size_t(k) * n + k];
      for (int c = 0; c < n; ++c) m[std::size_t(k) * n + c] /= d, inv[std::size_t(k) * n + c] /= d;
      for (int r = 0; r < n; ++r) {
        if (r == k) continue;
        const double f = m[std::size_t(r) * n + k];
        for (int c = 0; c < n; ++c) {
          m[std::size_t(r) * n + c] -= f * m[std::size_t(k) * n + c];
          inv[std::size_t(r) * n + c] -= f * inv[std::size_t(k) * n + c];
        }
      }
    }
    columns = inv;
  }
  const Gmres::Result exact = gmres.solve(denseMap(a, n), denseMap(columns, n), b, weights, n, 1e-8, x);
  CHECK(exact.steps == 1);
  CHECK(weightedRelativeResidual(a, n, x, b, weights) <= 1e-8);
}

TEST_CASE(
    "OT Newton system: the Jacobian product is the exact first-order area change, and directions solve "
    "J d = rhs to the tolerance") {
  constexpr int n = 32;
  OtSolverOptions options;
  options.threads = 2;
  OtGrid grid(n, options.threads);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  // A smooth potential small enough that its map folds no quad, and an arbitrary direction x.
  std::vector<double> psi(grid.cellCount()), x(grid.cellCount());
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      psi[grid.cell(i, j)] =
          2e-3 * std::cos(0.2 * i + 0.1) * std::sin(0.15 * j + 0.4) + 1e-3 * (i * j) / (n * n);
  for (double& v : x) v = 1e-3 * uni(rng);
  std::vector<glm::dvec2> positions(grid.vertexCount());
  grid.mapOf(psi, positions);
  REQUIRE(otFoldedQuads(positions, n) == 0);
  OtNewtonSystem newton(grid, options);
  std::vector<double> jx(grid.cellCount());
  newton.applyJacobian(positions, x, jx);
  // Every area is quadratic in t along psi + t x, so the central difference is J x up to rounding.
  constexpr double t = 0.5;
  std::vector<double> plus = psi, minus = psi;
  for (std::size_t c = 0; c < psi.size(); ++c) plus[c] += t * x[c], minus[c] -= t * x[c];
  std::vector<glm::dvec2> moved(grid.vertexCount());
  grid.mapOf(plus, moved);
  const std::vector<double> areasPlus = otQuadAreas(moved, n);
  grid.mapOf(minus, moved);
  const std::vector<double> areasMinus = otQuadAreas(moved, n);
  double largest = 0.0;
  for (double v : jx) largest = std::max(largest, std::abs(v));
  REQUIRE(largest > 0.0);
  for (std::size_t c = 0; c < jx.size(); ++c)
    CHECK((areasPlus[c] - areasMinus[c]) / (2.0 * t) == doctest::Approx(jx[c]).epsilon(1e-9).scale(largest));

  // Newton directions at this map towards a smooth mean-1 density's masses, with the Laplacian's GMRES and
  // with LU factors: GMRES to krylovTolerance in the 1/m-weighted norm, checked with the product above.
  const std::vector<double> areas = otQuadAreas(positions, n);
  std::vector<double> mass = smoothDensity(n), residual(grid.cellCount()), rhs(grid.cellCount());
  double total = 0.0;
  for (double v : mass) total += v;
  for (double& v : mass) v /= total;  // sums to 1, as the areas do
  for (std::size_t c = 0; c < rhs.size(); ++c) residual[c] = areas[c] - mass[c], rhs[c] = -residual[c];
  for (const bool luFirst : {false, true}) {
    CAPTURE(luFirst);
    OtNewtonSystem system(grid, options);
    if (luFirst) system.setLuFirst();
    std::vector<double> d(grid.cellCount()), jd(grid.cellCount());
    system.direction({positions, mass, residual}, rhs, d);
    system.applyJacobian(positions, d, jd);
    double e2 = 0.0, r2 = 0.0;
    for (std::size_t c = 0; c < rhs.size(); ++c) {
      e2 += (jd[c] - rhs[c]) / mass[c] * ((jd[c] - rhs[c]) / mass[c]);
      r2 += rhs[c] / mass[c] * (rhs[c] / mass[c]);
    }
    CHECK(std::sqrt(e2 / r2) <= options.krylovTolerance);
    CHECK(system.krylovSteps() >= 1);
    CHECK(system.factorisations() == (luFirst ? 1 : 0));
  }
}

TEST_CASE("OT multilevel: restriction keeps the mass, prolongation drops the checkerboard") {
  constexpr int m = 8, n = 2 * m;
  const std::vector<double> fine = sunDensity(n, 1e3);
  const std::vector<double> coarse = otRestrictDensity(fine, n);
  REQUIRE(coarse.size() == std::size_t(m) * m);
  double fineSum = 0.0, coarseSum = 0.0;
  for (double v : fine) fineSum += v;
  for (double v : coarse) coarseSum += v;
  CHECK(4.0 * coarseSum == doctest::Approx(fineSum).epsilon(1e-14));

  // The 2x2 gradient stencil does not see (-1)^(i+j) at interior vertices, so a coarse psi may carry any
  // amount of it; averaged at the coarse vertices, it prolongs to a constant except next to the four corners
  // (where the clamped average sees a single cell).
  std::vector<double> checkerboard(std::size_t(m) * m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) checkerboard[std::size_t(j) * m + i] = (i + j) % 2 == 0 ? 1.0 : -1.0;
  const std::vector<double> prolonged = otProlongPotential(checkerboard, m);
  REQUIRE(prolonged.size() == std::size_t(n) * n);
  const double middle = prolonged[std::size_t(n / 2) * n + n / 2];
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool nearCorner = (i < 2 || i >= n - 2) && (j < 2 || j >= n - 2);
      if (!nearCorner) CHECK(prolonged[std::size_t(j) * n + i] == middle);
    }
  double mean = 0.0;
  for (double v : prolonged) mean += v;
  CHECK(std::abs(mean) < 1e-14);
}

TEST_CASE("OT solver: bad input throws") {
  CHECK_THROWS_AS(solveOtMap(std::vector<double>(10, 1.0), 4), Error);
  CHECK_THROWS_AS(solveOtMap(std::vector<double>(16, 0.0), 4), Error);
  std::vector<double> negative(16, 1.0);
  negative[3] = -1.0;
  CHECK_THROWS_AS(solveOtMap(negative, 4), Error);
  negative[3] = std::nan("");
  CHECK_THROWS_AS(solveOtMap(negative, 4), Error);
  OtSolverOptions noKrylov;
  noKrylov.krylovSteps = 0;
  CHECK_THROWS_AS(solveOtMap(smoothDensity(4), 4, noKrylov), Error);
}

TEST_CASE("OT density: a constant environment gives sin(theta) integrated exactly over each cell") {
  // Sizes that are and are not multiples of the grid, so cells straddle texels in both directions.
  for (const auto& [w, h, n] : {std::array{64, 32, 16}, std::array{48, 24, 10}, std::array{30, 17, 7}}) {
    CAPTURE(w);
    CAPTURE(h);
    CAPTURE(n);
    const std::vector<double> d = otDensityFromEnv(constantEnv(w, h, 2.5f), n);
    REQUIRE(d.size() == std::size_t(n) * n);
    for (int j = 0; j < n; ++j) {
      // Mean-1 density of cell row j: n * (cos(pi j/n) - cos(pi (j+1)/n)) / 2 (the cell's share of 2, times
      // n^2).
      const double expected = n * (std::cos(kPiD * j / n) - std::cos(kPiD * (j + 1) / n)) / 2.0;
      for (int i = 0; i < n; ++i)
        CHECK(d[std::size_t(j) * n + i] == doctest::Approx(expected).epsilon(1e-12));
    }
  }
}

TEST_CASE("OT density: one bright texel lands in the cells it overlaps, in proportion") {
  // 4 x 2 map, one texel (1, 0) = 1, rest 0; n = 3: texel u in [1/4, 1/2] splits 1/12 : 2/12 between columns
  // 0 and 1; texel v in [0, 1/2] covers cell row 0 (v < 1/3) and part of row 1, by solid angle.
  test::NamedEnv env{"one", makeEnv(4, 2, [](int x, int y, double, double) {
                       const double v = (x == 1 && y == 0) ? 1.0 : 0.0;
                       return std::array<double, 3>{v, v, v};
                     })};
  const std::vector<double> d = otDensityFromEnv(env.image, 3);
  const double row0 = 1.0 - std::cos(kPiD / 3.0), row1 = std::cos(kPiD / 3.0) - 0.0;  // cos(0)-cos(pi/3), ...
  const double rowTotal = row0 + row1;
  const double col0 = 1.0 / 3.0, col1 = 2.0 / 3.0;
  const double cells = 9.0;
  CHECK(d[0] == doctest::Approx(cells * col0 * row0 / rowTotal));
  CHECK(d[1] == doctest::Approx(cells * col1 * row0 / rowTotal));
  CHECK(d[3] == doctest::Approx(cells * col0 * row1 / rowTotal));
  CHECK(d[4] == doctest::Approx(cells * col1 * row1 / rowTotal));
  CHECK(d[2] == 0.0);
  for (int c = 6; c < 9; ++c) CHECK(d[std::size_t(c)] == 0.0);
}

// Second-order correction (OtSolverOptions::secondOrderCorrection): on textured 10^5 suns, where the levels
// must undo continuation stages, steps cut short by the fold guard follow the corrected curve. Each map
// converges with no negative area, curved steps are taken, and together they need fewer Newton iterations
// than the straight steps (measured 152 against 195 here; 14 of 15 such densities at n = 64 and 128 took
// fewer). A wrong correction (a sign, a stale direction) is rejected by the step's merit test and takes no
// curved step, or takes worse ones.
TEST_CASE("OT solver: curved steps on textured suns converge in fewer Newton iterations") {
  constexpr int n = 64;
  int curvedIterations = 0, straightIterations = 0, curvedSteps = 0;
  for (int seed = 1; seed <= 4; ++seed)
    for (bool curved : {true, false}) {
      CAPTURE(seed);
      CAPTURE(curved);
      OtSolverOptions options;
      options.threads = 2;  // the reductions' chunks, so the counts do not depend on the machine
      options.secondOrderCorrection = curved;
      const OtMap map = solveOtMap(textured(sunDensity(n, 1e5), 3.0, seed), n, options);
      CHECK(map.converged);
      CHECK(map.negativeAreaQuads == 0);
      const int iterations = map.iterations + map.coarseIterations;
      (curved ? curvedIterations : straightIterations) += iterations;
      for (const OtLevelStats& level : map.levels) {
        if (!curved) CHECK(level.curvedSteps == 0);
        curvedSteps += level.curvedSteps;
      }
    }
  MESSAGE("Newton iterations, curved against straight: " << curvedIterations << " / " << straightIterations
                                                         << " (" << curvedSteps << " curved steps)");
  CHECK(curvedSteps > 0);
  CHECK(curvedIterations < straightIterations);
}
