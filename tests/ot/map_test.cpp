// Tests of QuadGridMap (engine/ot/map.h): piece classification, evaluation and inversion of each
// piece, apply/invert round trips on solved OT maps, that the Jacobian integrates to each piece's image area,
// that inverted uniform points land in each cell with the probability of its image area (chi-square), and the
// tabulated inverse: forward(inverse(u)) = u at its vertices and close to u between them.
#include "engine/ot/map.h"

#include "engine/ot/solver.h"

#include "tests/support/ot_densities.h"

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace iblx;
using namespace iblx::test;
using glm::dvec2;

namespace {

double cross(dvec2 a, dvec2 b) {
  return a.x * b.y - a.y * b.x;
}

// Image area of cell c's piece: the quad's signed area (both splits and the bilinear patch have it).
double pieceArea(const QuadGridMap& map, std::size_t c) {
  const int m = map.size(), i = int(c % std::size_t(m)), j = int(c / std::size_t(m));
  const auto v = map.image();
  const std::size_t p = std::size_t(j) * (m + 1) + i;
  return 0.5 * cross(v[p + m + 2] - v[p], v[p + m + 1] - v[p + 1]);
}

}  // namespace

TEST_CASE(
    "classifyQuad: convex quads are bilinear, darts are split through the reflex corner, bow ties invalid") {
  CHECK(classifyQuad({0, 0}, {1, 0}, {1, 1}, {0, 1}) == QuadPiece::Bilinear);
  // Reflex corner at 11 (pushed inside): the split through 11 is the main diagonal 00-11.
  CHECK(classifyQuad({0, 0}, {1, 0}, {0.3, 0.3}, {0, 1}) == QuadPiece::SplitMainDiagonal);
  // Reflex corner at 10: the anti-diagonal 10-01.
  CHECK(classifyQuad({0, 0}, {0.3, 0.3}, {1, 1}, {0, 1}) == QuadPiece::SplitAntiDiagonal);
  CHECK(classifyQuad({0, 0}, {1, 1}, {1, 0}, {0, 1}) == QuadPiece::Invalid);  // self-intersecting
  CHECK(classifyQuad({0, 0}, {0, 1}, {1, 1}, {1, 0}) == QuadPiece::Invalid);  // clockwise
}

TEST_CASE("evaluatePiece / invertPiece: corners, round trips and the Jacobian of every piece") {
  const dvec2 convex[4] = {{0.1, 0.0}, {1.0, 0.2}, {0.9, 1.1}, {-0.1, 0.8}};
  const dvec2 dart[4] = {{0, 0}, {1, 0}, {0.4, 0.35}, {0, 1}};
  const dvec2 antiDart[4] = {{0, 0}, {0.35, 0.4}, {1, 1}, {0, 1}};
  const struct {
    const dvec2* c;
    QuadPiece piece;
  } cases[] = {{convex, QuadPiece::Bilinear},
               {dart, QuadPiece::SplitMainDiagonal},
               {antiDart, QuadPiece::SplitAntiDiagonal}};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const auto& k : cases) {
    REQUIRE(classifyQuad(k.c[0], k.c[1], k.c[2], k.c[3]) == k.piece);
    CHECK(glm::length(evaluatePiece(k.piece, k.c, {0, 0}, nullptr) - k.c[0]) < 1e-15);
    CHECK(glm::length(evaluatePiece(k.piece, k.c, {1, 0}, nullptr) - k.c[1]) < 1e-15);
    CHECK(glm::length(evaluatePiece(k.piece, k.c, {1, 1}, nullptr) - k.c[2]) < 1e-15);
    CHECK(glm::length(evaluatePiece(k.piece, k.c, {0, 1}, nullptr) - k.c[3]) < 1e-15);
    double integral = 0.0;
    for (int s = 0; s < 400; ++s) {
      const dvec2 st(uniform(rng), uniform(rng));
      double jac = 0.0;
      const dvec2 y = evaluatePiece(k.piece, k.c, st, &jac);
      CHECK(jac > 0.0);
      dvec2 back;
      REQUIRE(invertPiece(k.piece, k.c, y, back));
      CHECK(glm::length(back - st) < 1e-10);
      // Finite-difference Jacobian (away from the split diagonal, where it jumps).
      const double eps = 1e-6;
      if (std::abs(st.x - st.y) > 1e-3 && std::abs(st.x + st.y - 1.0) > 1e-3 && st.x > eps && st.y > eps &&
          st.x < 1 - eps && st.y < 1 - eps) {
        const dvec2 dx = (evaluatePiece(k.piece, k.c, st + dvec2(eps, 0), nullptr) -
                          evaluatePiece(k.piece, k.c, st - dvec2(eps, 0), nullptr)) /
                         (2 * eps);
        const dvec2 dy = (evaluatePiece(k.piece, k.c, st + dvec2(0, eps), nullptr) -
                          evaluatePiece(k.piece, k.c, st - dvec2(0, eps), nullptr)) /
                         (2 * eps);
        CHECK(cross(dx, dy) == doctest::Approx(jac).epsilon(1e-6));
      }
    }
    // The Jacobian integrates to the quad's area (midpoint rule on a fine grid; exact for affine pieces away
    // from the diagonal, second order for the bilinear one).
    const int g = 200;
    for (int a = 0; a < g; ++a)
      for (int b = 0; b < g; ++b) {
        double jac = 0.0;
        evaluatePiece(k.piece, k.c, {(a + 0.5) / g, (b + 0.5) / g}, &jac);
        integral += jac / (g * g);
      }
    const double area = 0.5 * cross(k.c[2] - k.c[0], k.c[3] - k.c[1]);
    CHECK(integral == doctest::Approx(area).epsilon(2e-3));
    // A point outside the quad is not inverted.
    dvec2 st;
    CHECK_FALSE(invertPiece(k.piece, k.c, {2.0, 2.0}, st));
  }
}

TEST_CASE("QuadGridMap on solved OT maps: round trips, areas, chi-square of inverted uniform points") {
  for (const auto& [name, density] : {std::pair{std::string("sun1e5"), sunDensity(32, 1e5)},
                                      std::pair{std::string("halfzero"), halfZeroDensity(32)},
                                      std::pair{std::string("sun1e3"), sunDensity(32, 1e3)}}) {
    CAPTURE(name);
    const OtMap ot = solveOtMap(density, 32);
    REQUIRE(ot.converged);
    const QuadGridMap forward = forwardMap(ot);
    CHECK(forward.invalidPieces() == 0);
    if (name != "halfzero") {  // the solver's own map has twisted quads next to the sun: the regression case
      const QuadGridMap raw(32, ot.vertices);
      CHECK(raw.invalidPieces() > 0);
    }
    double total = 0.0;
    for (std::size_t c = 0; c < std::size_t(32 * 32); ++c) total += pieceArea(forward, c);
    CHECK(total == doctest::Approx(1.0).epsilon(1e-12));

    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (int s = 0; s < 2000; ++s) {
      const dvec2 x(uniform(rng), uniform(rng));
      const auto y = forward.apply(x);
      const auto back = forward.invert(y.p);
      REQUIRE(back.has_value());
      // A point on a collapsed (zero-density) piece may come back in a neighbour: compare images then.
      CHECK(glm::length(forward.apply(back->p).p - y.p) < 1e-9);
      CHECK(back->jacobian == doctest::Approx(y.jacobian).epsilon(1e-6));
    }

    // Uniform u inverted: cell c is hit with probability = its piece's image area.
    const int samples = 200000;
    std::vector<double> hits(32 * 32, 0.0);
    for (int s = 0; s < samples; ++s) {
      const auto x = forward.invert({uniform(rng), uniform(rng)});
      REQUIRE(x.has_value());
      hits[x->cell] += 1.0;
    }
    double chi2 = 0.0;
    int dof = 0;
    double pooledExpected = 0.0, pooledHits = 0.0;
    for (std::size_t c = 0; c < hits.size(); ++c) {
      const double expected = samples * pieceArea(forward, c);
      if (expected < 5.0) {
        pooledExpected += expected, pooledHits += hits[c];
        continue;
      }
      chi2 += (hits[c] - expected) * (hits[c] - expected) / expected;
      ++dof;
    }
    if (pooledExpected >= 5.0)
      chi2 += (pooledHits - pooledExpected) * (pooledHits - pooledExpected) / pooledExpected, ++dof;
    // Wilson-Hilferty: the 0.999 quantile of chi-square with k dof.
    const double k = dof - 1, z = 3.09;
    const double bound = k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3.0);
    CHECK(chi2 < bound);
  }
}

TEST_CASE("tabulatedInverse: forward(inverse(u)) = u at the vertices, close between them; boundary kept") {
  const OtMap ot = solveOtMap(sunDensity(32, 1e3), 32);
  REQUIRE(ot.converged);
  const QuadGridMap forward = forwardMap(ot);
  const QuadGridMap inverse = tabulatedInverse(forward, 32);
  CHECK(inverse.invalidPieces() == 0);
  const auto image = inverse.image();
  for (int j = 0; j <= 32; ++j)
    for (int i = 0; i <= 32; ++i) {
      const dvec2 u(i / 32.0, j / 32.0);
      const dvec2 x = image[std::size_t(j) * 33 + i];
      CHECK(glm::length(forward.apply(x).p - u) < 1e-9);
      if (i == 0 || i == 32) CHECK(x.x == u.x);
      if (j == 0 || j == 32) CHECK(x.y == u.y);
    }
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double worst = 0.0;
  for (int s = 0; s < 2000; ++s) {
    const dvec2 u(uniform(rng), uniform(rng));
    const auto x = inverse.apply(u);
    worst = std::max(worst, glm::length(forward.apply(x.p).p - u));
    const auto back = inverse.invert(x.p);
    REQUIRE(back.has_value());
    CHECK(glm::length(back->p - u) < 1e-9);
  }
  CHECK(worst < 0.05);  // the tabulation error between vertices, at most a fraction of a cell
}
