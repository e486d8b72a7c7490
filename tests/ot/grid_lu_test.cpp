// Tests of the nested-dissection multifrontal LU (engine/ot/grid_lu.h): solutions against a dense
// Gaussian elimination on small grids of every shape, row pivoting inside a front, the OT Jacobian's pinned
// row, threads giving identical results, and zero pivots replaced instead of dividing by zero.
#include "engine/ot/grid_lu.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace iblx;

namespace {

// A random nine-point matrix, unsymmetric, made diagonally dominant by `dominance` (0: none).
StencilMatrix randomStencil(int w, int h, unsigned seed, double dominance) {
  StencilMatrix a(w, h);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (double& value : a.values) value = uniform(rng);
  for (int c = 0; c < w * h; ++c) a.at(c, 0, 0) += dominance * (a.at(c, 0, 0) < 0.0 ? -1.0 : 1.0);
  return a;
}

// Dense Gaussian elimination with partial pivoting over all rows.
std::vector<double> denseSolve(const StencilMatrix& a, std::vector<double> b) {
  const int size = a.width * a.height;
  std::vector<double> m(std::size_t(size) * size, 0.0);
  for (int c = 0; c < size; ++c)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = c % a.width + dx, y = c / a.width + dy;
        if (x >= 0 && x < a.width && y >= 0 && y < a.height)
          m[std::size_t(c) * size + y * a.width + x] = a.at(c, dx, dy);
      }
  for (int k = 0; k < size; ++k) {
    int pivot = k;
    for (int i = k + 1; i < size; ++i)
      if (std::abs(m[std::size_t(i) * size + k]) > std::abs(m[std::size_t(pivot) * size + k])) pivot = i;
    for (int j = 0; j < size; ++j) std::swap(m[std::size_t(k) * size + j], m[std::size_t(pivot) * size + j]);
    std::swap(b[std::size_t(k)], b[std::size_t(pivot)]);
    for (int i = k + 1; i < size; ++i) {
      const double f = m[std::size_t(i) * size + k] / m[std::size_t(k) * size + k];
      for (int j = k; j < size; ++j) m[std::size_t(i) * size + j] -= f * m[std::size_t(k) * size + j];
      b[std::size_t(i)] -= f * b[std::size_t(k)];
    }
  }
  for (int k = size - 1; k >= 0; --k) {
    for (int j = k + 1; j < size; ++j) b[std::size_t(k)] -= m[std::size_t(k) * size + j] * b[std::size_t(j)];
    b[std::size_t(k)] /= m[std::size_t(k) * size + k];
  }
  return b;
}

std::vector<double> randomVector(int size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> v(static_cast<std::size_t>(size));
  for (double& x : v) x = uniform(rng);
  return v;
}

double maxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// max |a - b| / max |b|.
double relativeDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double scale = 0.0;
  for (double v : b) scale = std::max(scale, std::abs(v));
  return maxDifference(a, b) / scale;
}

// A^-1 b by the factors, then `refinements` steps of iterative refinement: the factors are kept in single
// precision, and each step gains about as many digits again.
std::vector<double> luSolve(GridLu& lu, const StencilMatrix& a, const std::vector<double>& b,
                            int refinements) {
  std::vector<double> x = b, r(b.size());
  lu.solve(x);
  for (int k = 0; k < refinements; ++k) {
    a.multiply(x, r);
    for (std::size_t i = 0; i < r.size(); ++i) r[i] = b[i] - r[i];
    lu.solve(r);
    for (std::size_t i = 0; i < r.size(); ++i) x[i] += r[i];
  }
  return x;
}

}  // namespace

TEST_CASE("Grid LU: solutions match dense elimination on grids of every shape") {
  // 1x1 and 4x4 are single leaves; 5x4 splits once; 17x3, 3x17 and the strips 64x1, 1x64 and 2x40 split
  // along their long side only; 13x11 and 31x29 nest several separators, with fronts whose boundary rings
  // touch the grid's edges and corners. Between them the fronts' own sizes take every value mod 4, the unit
  // the solves' factor layout works in (grid_lu.cpp); 7x6's root has 6 own variables and no boundary: one
  // block of four columns and two single ones, with no boundary rows.
  const int shapes[][2] = {{1, 1},  {4, 4},  {5, 4}, {17, 3},  {3, 17}, {64, 1},
                           {1, 64}, {2, 40}, {7, 6}, {13, 11}, {31, 29}};
  unsigned seed = 1;
  for (const auto& shape : shapes) {
    const int w = shape[0], h = shape[1];
    CAPTURE(w);
    CAPTURE(h);
    const StencilMatrix a = randomStencil(w, h, seed, 4.0);
    const std::vector<double> b = randomVector(w * h, seed + 100);
    ++seed;
    GridLu lu(w, h, 1);
    CHECK(lu.factor(a) == 0);
    const std::vector<double> exact = denseSolve(a, b);
    CHECK(relativeDifference(luSolve(lu, a, b, 0), exact) < 1e-5);
    const std::vector<double> x = luSolve(lu, a, b, 2);
    CHECK(relativeDifference(x, exact) < 1e-12);
    std::vector<double> ax(b.size());
    a.multiply(x, ax);
    CHECK(maxDifference(ax, b) < 1e-11);
  }
}

TEST_CASE("Grid LU: pivots inside a front when the diagonal is small or zero") {
  // No diagonal dominance, and zero diagonal entries in a leaf and on a separator: elimination without row
  // interchanges would divide by zero or by tiny pivots.
  StencilMatrix a = randomStencil(9, 7, 7, 0.0);
  for (int c : {0, 4, 9 * 3 + 4, 9 * 6 + 8}) a.at(c, 0, 0) = 0.0;
  const std::vector<double> b = randomVector(9 * 7, 8);
  GridLu lu(9, 7, 1);
  CHECK(lu.factor(a) == 0);
  const std::vector<double> exact = denseSolve(a, b);
  CHECK(relativeDifference(luSolve(lu, a, b, 0), exact) < 1e-4);
  CHECK(relativeDifference(luSolve(lu, a, b, 3), exact) < 1e-11);
}

TEST_CASE("Grid LU: the OT Jacobian's pinned row, and a refactorisation with new values") {
  // Row 0 = e_0 (psi_0 = 0), as engine/ot/solver.cpp assembles it; the other rows sum to 0 like the area
  // Jacobian.
  const int n = 24;
  StencilMatrix a = randomStencil(n, n, 11, 0.0);
  for (int c = 0; c < n * n; ++c) {
    double offDiagonal = 0.0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = c % n + dx, y = c / n + dy;
        const bool inside = x >= 0 && x < n && y >= 0 && y < n;
        if (dx == 0 && dy == 0) continue;
        a.at(c, dx, dy) = inside ? -std::abs(a.at(c, dx, dy)) : 0.0;
        offDiagonal += a.at(c, dx, dy);
      }
    a.at(c, 0, 0) = -offDiagonal;
  }
  std::fill_n(a.values.begin(), 9, 0.0);
  a.at(0, 0, 0) = 1.0;
  GridLu lu(n, n, 2);
  const std::vector<double> b = randomVector(n * n, 12);
  for (int round = 0; round < 2; ++round) {
    CAPTURE(round);
    if (round == 1)
      for (int c = 1; c < n * n; ++c) a.at(c, 0, 0) *= 1.5;  // same pattern, new values
    CHECK(lu.factor(a) == 0);
    CHECK(relativeDifference(luSolve(lu, a, b, 2), denseSolve(a, b)) < 1e-10);
  }
}

TEST_CASE("Grid LU: threads give bit-identical solutions") {
  // Without diagonal dominance, so that fronts on every thread pivot; 3 and 16 threads split unevenly or
  // more often than the tree allows on the small grid.
  const StencilMatrix a = randomStencil(40, 37, 21, 0.0), small = randomStencil(5, 4, 23, 0.0);
  const std::vector<double> b = randomVector(40 * 37, 22), bSmall = randomVector(5 * 4, 24);
  GridLu one(40, 37, 1);
  one.factor(a);
  std::vector<double> x1 = b;
  one.solve(x1);
  CHECK(relativeDifference(luSolve(one, a, b, 3), denseSolve(a, b)) < 1e-10);
  for (int threads : {2, 3, 4}) {
    CAPTURE(threads);
    GridLu many(40, 37, threads);
    many.factor(a);
    std::vector<double> x = b;
    many.solve(x);
    CHECK(maxDifference(x1, x) == 0.0);
  }
  GridLu smallOne(5, 4, 1), smallMany(5, 4, 16);
  smallOne.factor(small), smallMany.factor(small);
  std::vector<double> s1 = bSmall, s16 = bSmall;
  smallOne.solve(s1), smallMany.solve(s16);
  CHECK(maxDifference(s1, s16) == 0.0);
}

TEST_CASE("Grid LU: a singular matrix has its zero pivots replaced, and the solve stays finite") {
  SUBCASE("diagonal with zeros: the nonzero rows are still solved exactly") {
    StencilMatrix a(6, 5);
    for (int c = 0; c < 30; c += 3) a.at(c, 0, 0) = 2.0;
    GridLu lu(6, 5, 1);
    CHECK(lu.factor(a) == 20);
    const std::vector<double> b = randomVector(30, 3);
    std::vector<double> x = b;
    lu.solve(x);
    for (int c = 0; c < 30; ++c) {
      CHECK(std::isfinite(x[std::size_t(c)]));
      if (c % 3 == 0) CHECK(x[std::size_t(c)] == doctest::Approx(b[std::size_t(c)] / 2.0).epsilon(1e-6));
    }
  }
  SUBCASE("zero pivot columns: in a leaf with entries below it, and on a separator") {
    // 9x3: the separator is column x = 4 (cells 4, 13, 22), the right leaf is x = 5..8. Column 5 (the leaf's
    // first pivot) is zeroed in the leaf's own rows only, so the separator rows below keep entries there
    // (L21 = F21 / tiny pivot); column 13 (on the separator) is zeroed everywhere.
    StencilMatrix a = randomStencil(9, 3, 31, 4.0);
    for (int zero : {5, 13})
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = zero % 9 - dx, y = zero / 9 - dy;  // the row whose (dx, dy) entry is column `zero`
          const bool keep = zero == 5 && x == 4;
          if (x >= 0 && x < 9 && y >= 0 && y < 3 && !keep) a.at(y * 9 + x, dx, dy) = 0.0;
        }
    GridLu lu(9, 3, 2);
    CHECK(lu.factor(a) >= 2);
    std::vector<double> x = randomVector(27, 32);
    lu.solve(x);
    for (double value : x) CHECK(std::isfinite(value));
  }
}
