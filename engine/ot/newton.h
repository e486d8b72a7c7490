// The Newton system of the OT solver's area equations on one level: J d = -r, with J the exact Jacobian of
// the quad areas with respect to the potential at the current map and r the area residual. Directions come
// from GMRES (gmres.h), right-preconditioned by the fixed pseudo-Laplacian L while that reaches the
// tolerance, else by LU factors of J at an earlier map (grid_lu.h), renewed when they go stale. L is the
// Jacobian at the identity and is diagonal in the DCT-II basis (dct.h); -L^-1 r is the chord direction of
// Nader & Guennebaud 2018, "Instant transport maps on 2D grids", ACM TOG 37(6), and GMRES's first Krylov
// vector, so these directions are never worse than it in ||r + J d||.
#pragma once

#include "engine/ot/grid_lu.h"
#include "engine/ot/dct.h"
#include "engine/ot/gmres.h"
#include "engine/ot/grid.h"
#include "engine/ot/solver.h"

#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <vector>

namespace iblx {

class OtNewtonSystem {
 public:
  // Keeps references to grid and options, which must outlive it.
  OtNewtonSystem(OtGrid& grid, const OtSolverOptions& options);

  // d with J d ~ rhs (rhs = -r for a Newton direction) at `map`: GMRES(krylovSteps) to krylovTolerance,
  // relative to the target masses when options.relativeResidual.
  void direction(const OtMapState& map, std::span<const double> rhs, std::span<double> d);
  // d2 ~ -J^-1 a with the current LU factors (no GMRES: it need not be exact), or -L^-1 a before there are
  // any: the second-order correction of a curved step.
  void correction(std::span<const double> a, std::span<double> d2);
  // out = J x at `positions`: the linear coefficient of every quad's area when psi moves by t x.
  void applyJacobian(std::span<const glm::dvec2> positions, std::span<const double> x, std::span<double> out);

  // True once the Laplacian-preconditioned GMRES missed its tolerance on this level (the map is too
  // distorted for it); from then on directions use the LU factors.
  bool laplacianFailed() const { return laplacianFailed_; }
  // Starts with LU-preconditioned directions: the coarser level ended with them, so the Laplacian's GMRES
  // would most likely fail here too, at the cost of krylovSteps DCT solves.
  void setLuFirst() { laplacianFailed_ = true; }
  int factorisations() const { return factorisations_; }
  int krylovSteps() const { return krylovSteps_; }

 private:
  enum class Preconditioner { Laplacian, FrozenLu };

  // GMRES on J x = rhs preconditioned by `which`; returns the relative residual reached.
  double gmres(const OtMapState& map, std::span<const double> rhs, std::span<double> x, Preconditioner which,
               int maxSteps, double tolerance);
  // out = (-L)^-1 r in the DCT-II basis.
  void solveLaplacian(std::span<const double> r, std::span<double> out);
  // out = sign * J^-1 rhs with the current LU factors; non-finite entries of the solution become 0.
  void solveFrozenLu(std::span<const double> rhs, std::span<double> out, double sign);
  // LU factors of the exact Jacobian at `positions`.
  void factorJacobian(std::span<const glm::dvec2> positions);

  OtGrid& grid_;
  const OtSolverOptions& options_;
  DctPlan dct_;
  std::vector<double> inverseEigen_;  // 1 / the eigenvalues of -L in the DCT-II basis (0 for the mean)
  std::vector<glm::dvec2> motion_;    // the vertex motion of a Jacobian product
  std::vector<double> rowWeights_;    // GMRES's row weights, 1/m or 1
  Gmres gmres_;
  StencilMatrix jacobian_;
  std::optional<GridLu> lu_;  // the nested dissection is computed once per level, at the first factorisation
  bool laplacianFailed_ = false;
  int factorisations_ = 0, krylovSteps_ = 0;
};

}  // namespace iblx
