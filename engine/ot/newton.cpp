// The OT solver's Newton system (newton.h): the Jacobian product and assembly, the pseudo-Laplacian's DCT
// solve, the LU factors and the choice between them.
#include "engine/ot/newton.h"

#include "engine/core/sphere_mapping.h"
#include "engine/ot/geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace iblx {

namespace {

using Vec2 = glm::dvec2;

// Linear coefficient of the area of quad q when its vertices move by t * g: with diagonals D1 = P11 - P00,
// D2 = P01 - P10, A(t) = ½ (D1 + t E1) x (D2 + t E2) (the quad area of Nader & Guennebaud 2018).
double linearCoefficient(const OtQuad& q, std::span<const Vec2> pos, std::span<const Vec2> g) {
  const Vec2 d1 = pos[q.p11] - pos[q.p00], d2 = pos[q.p01] - pos[q.p10];
  const Vec2 e1 = g[q.p11] - g[q.p00], e2 = g[q.p01] - g[q.p10];
  return 0.5 * (cross2(d1, e2) + cross2(e1, d2));
}

}  // namespace

OtNewtonSystem::OtNewtonSystem(OtGrid& grid, const OtSolverOptions& options)
    : grid_(grid), options_(options), dct_(grid.n()), motion_(grid.vertexCount()) {
  const int n = grid.n();
  // Eigenvalues of -L = 2 (I - A (x) A), A the clamped 1-D average with eigenvalues cos(pi k / n) (DCT-II).
  inverseEigen_.resize(grid.cellCount());
  for (int k = 0; k < n; ++k)
    for (int l = 0; l < n; ++l) {
      const double lambda = 2.0 * (1.0 - std::cos(kPi * k / n) * std::cos(kPi * l / n));
      inverseEigen_[std::size_t(k) * n + l] = (k == 0 && l == 0) ? 0.0 : 1.0 / lambda;  // mean of d is 0
    }
}

// The factors are lagged: those of the Jacobian at an earlier map, close to the current one within a
// continuation stage. A factorisation costs as much as many LU solves (docs/ot_solver.md, section 7), so they
// are kept as long as GMRES fixes their mismatch in a few steps. They are asked for a tighter tolerance than
// fresh ones, which meet krylovTolerance in one or two steps and so give nearly exact directions: lagged
// factors at krylovTolerance give inexact directions that cost more Newton iterations than the factorisations
// saved. A short step is no sign of poor factors (the fold guard cuts the first step of most continuation
// stages), so only GMRES's own progress renews them.
void OtNewtonSystem::direction(const OtMapState& map, std::span<const double> rhs, std::span<double> d) {
  const int steps = options_.krylovSteps;
  if (!laplacianFailed_) {
    if (gmres(map, rhs, d, Preconditioner::Laplacian, steps, options_.krylovTolerance) <=
        options_.krylovTolerance)
      return;
    laplacianFailed_ = true;
  }
  constexpr int kLaggedSteps = 4;
  constexpr double kLaggedTolerance = 0.03;
  if (lu_ && gmres(map, rhs, d, Preconditioner::FrozenLu, std::min(kLaggedSteps, steps), kLaggedTolerance) <=
                 kLaggedTolerance)
    return;
  factorJacobian(map.positions);
  gmres(map, rhs, d, Preconditioner::FrozenLu, steps, options_.krylovTolerance);
}

void OtNewtonSystem::correction(std::span<const double> a, std::span<double> d2) {
  if (lu_)
    solveFrozenLu(a, d2, -1.0);
  else
    solveLaplacian(a, d2);
}

double OtNewtonSystem::gmres(const OtMapState& map, std::span<const double> rhs, std::span<double> x,
                             Preconditioner which, int maxSteps, double tolerance) {
  // Relative residuals (A - m) / m: the rows weighted by 1/m, so that the 2-norm tolerance bounds each quad's
  // error relative to its own target and the sun's cells cannot hide a 100 % error on a sky cell.
  rowWeights_.assign(rhs.size(), 1.0);
  if (options_.relativeResidual)
    for (std::size_t c = 0; c < rhs.size(); ++c) rowWeights_[c] = 1.0 / map.mass[c];
  const auto apply = [&](std::span<const double> in, std::span<double> out) {
    applyJacobian(map.positions, in, out);
  };
  const auto precondition = [&](std::span<const double> in, std::span<double> out) {
    if (which == Preconditioner::FrozenLu) {
      solveFrozenLu(in, out, 1.0);
      return;
    }
    solveLaplacian(in, out);
    for (double& value : out) value = -value;
  };
  const Gmres::Result result = gmres_.solve(apply, precondition, rhs, rowWeights_, maxSteps, tolerance, x);
  krylovSteps_ += result.steps;
  return result.relativeResidual;
}

void OtNewtonSystem::applyJacobian(std::span<const Vec2> positions, std::span<const double> x,
                                   std::span<double> out) {
  grid_.gradient(x, motion_);
  const int n = grid_.n();
  parallelChunks(grid_.threads(), n, 8, [&](int lo, int hi) {
    for (int j = lo; j < hi; ++j)
      for (int i = 0; i < n; ++i)
        out[grid_.cell(i, j)] = linearCoefficient(grid_.quad(i, j), positions, motion_);
  });
}

// The transposed layout between the two passes is harmless because the spectrum 1/lambda(k, l) is symmetric.
void OtNewtonSystem::solveLaplacian(std::span<const double> r, std::span<double> out) {
  const int n = grid_.n(), threads = grid_.threads();
  std::copy(r.begin(), r.end(), out.begin());
  dct_.forwardRows(out, threads);
  transposeSquare(out, n);
  dct_.forwardRows(out, threads);
  for (std::size_t c = 0; c < out.size(); ++c) out[c] *= inverseEigen_[c];
  dct_.inverseRows(out, threads);
  transposeSquare(out, n);
  dct_.inverseRows(out, threads);
}

void OtNewtonSystem::solveFrozenLu(std::span<const double> rhs, std::span<double> out, double sign) {
  std::copy(rhs.begin(), rhs.begin() + std::ptrdiff_t(grid_.cellCount()), out.begin());
  out[0] = 0.0;  // row 0 of the factored matrix is psi_0 = 0
  lu_->solve(out);
  for (double& value : out) value = std::isfinite(value) ? sign * value : 0.0;
}

// J (n^2 x n^2, 3x3 cell stencil) is assembled from the chain dA_c/dP_v (rotated diagonals) times dP_v/dpsi
// (the clamped 2x2 difference of OtGrid::gradient). J's rows sum to 0 (the total area is fixed) and
// constants are its null space (a constant potential does not move the map), so row 0 is replaced by psi_0 =
// 0. The pattern never changes, so its ordering is computed once per level.
void OtNewtonSystem::factorJacobian(std::span<const Vec2> positions) {
  const int n = grid_.n();
  if (!lu_) {
    lu_.emplace(n, n, grid_.threads());
    jacobian_ = StencilMatrix(n, n);
  }
  const double half = 0.5 * n;
  parallelChunks(grid_.threads(), n, 8, [&](int lo, int hi) {
    for (int j = lo; j < hi; ++j)
      for (int i = 0; i < n; ++i) {
        const int c = j * n + i;
        std::fill_n(jacobian_.values.begin() + std::ptrdiff_t(c) * 9, 9, 0.0);
        if (c == 0) {
          jacobian_.at(0, 0, 0) = 1.0;
          continue;
        }
        const OtQuad q = grid_.quad(i, j);
        const Vec2 d1 = positions[q.p11] - positions[q.p00], d2 = positions[q.p01] - positions[q.p10];
        // b = ½ (d1 x e2 + e1 x d2), e1 = g11 - g00, e2 = g01 - g10.
        const Vec2 de1 = 0.5 * Vec2(d2.y, -d2.x), de2 = 0.5 * Vec2(-d1.y, d1.x);
        const std::array<std::pair<int, Vec2>, 4> corners{
            std::pair{0, -de1}, std::pair{1, -de2}, std::pair{2, de1}, std::pair{3, de2}};  // 00, 10, 11, 01
        for (const auto& [corner, w] : corners) {
          const int vx = i + (corner == 1 || corner == 2 ? 1 : 0), vy = j + (corner >= 2 ? 1 : 0);
          // g = half * ((b - a) + (d - c), (c - a) + (d - b)), cells a = (vx-1, vy-1), b = (vx, vy-1),
          // c = (vx-1, vy), d = (vx, vy), clamped to the grid.
          const int x0 = std::clamp(vx - 1, 0, n - 1) - i, x1 = std::clamp(vx, 0, n - 1) - i;
          const int y0 = std::clamp(vy - 1, 0, n - 1) - j, y1 = std::clamp(vy, 0, n - 1) - j;
          jacobian_.at(c, x0, y0) += -half * (w.x + w.y), jacobian_.at(c, x1, y0) += half * (w.x - w.y);
          jacobian_.at(c, x0, y1) += half * (w.y - w.x), jacobian_.at(c, x1, y1) += half * (w.x + w.y);
        }
      }
  });
  // Exact zero pivots are replaced (GridLu's static pivoting): the factors then precondition a nearby
  // matrix, which GMRES's residual check still measures against the true one.
  lu_->factor(jacobian_);
  ++factorisations_;
}

}  // namespace iblx
