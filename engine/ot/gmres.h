// GMRES for the OT solver's Newton systems (Saad & Schultz 1986, "GMRES: a generalized minimal residual
// algorithm for solving nonsymmetric linear systems", SIAM J. Sci. Stat. Comput. 7(3)): no restart,
// right-preconditioned, with the residual measured in a row-weighted 2-norm. Independent of the OT problem:
// the operator and the preconditioner are callbacks.
#pragma once

#include <functional>
#include <span>
#include <vector>

namespace iblx {

class Gmres {
 public:
  // out = M in for a linear map M (out has the size of in and does not alias it).
  using LinearMap = std::function<void(std::span<const double> in, std::span<double> out)>;

  struct Result {
    double relativeResidual = 0.0;  // ||W (b - A x)|| / ||W b|| reached (0 for b = 0)
    int steps = 0;                  // Krylov steps: preconditioner solves and products with A
  };

  // x minimising ||W (b - A x)||_2 over x0 = 0 plus the Krylov space of W A M W^-1 from W b, W =
  // diag(rowWeights) (positive), M ~ A^-1 the right preconditioner: at most maxSteps steps, stopping once the
  // relative residual is at most `tolerance`. The weights make the 2-norm tolerance bound each row's error
  // relative to its own scale. The preconditioned vectors z_k = M W^-1 v_k are kept, so x = sum y_k z_k costs
  // no further preconditioner solve (as flexible GMRES stores them: Saad 1993, "A flexible inner-outer
  // preconditioned GMRES algorithm", SIAM J. Sci. Comput. 14(2)).
  Result solve(const LinearMap& apply, const LinearMap& precondition, std::span<const double> b,
               std::span<const double> rowWeights, int maxSteps, double tolerance, std::span<double> x);

 private:
  // The Krylov basis v_k (W-weighted, orthonormal) and z_k, sized as the iteration reaches them: most of the
  // OT solver's directions take a few steps, and sizing all 2 m + 1 up front would touch fresh pages for
  // nothing.
  std::vector<std::vector<double>> basis_, preconditioned_;
  std::vector<double> unweighted_;  // W^-1 v_k
};

}  // namespace iblx
