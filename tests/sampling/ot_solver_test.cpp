// Tests of the OT map solver (engine/sampling/ot_solver.h) and its DCT (engine/sampling/ot_dct.h): transforms
// against their definition, the identity map, mass residuals and folds on smooth, sun and half-zero
// densities, boundary vertices, the density of a lat-long environment against the analytic sin(theta)
// integral, bad input.
#include "engine/sampling/ot_solver.h"

#include "engine/core/error.h"
#include "engine/sampling/ot_dct.h"
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
