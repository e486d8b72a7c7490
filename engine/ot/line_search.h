// Step lengths of the OT solver along a vertex motion G (the gradient of a Newton direction). Every quad's
// area is quadratic in the step, A_c(P + t G) = A_c + b_c t + a_c t^2, so the squared-residual merit is a
// quartic in t and the first t at which a quad degenerates is a root of a quadratic: both are exact, with no
// trial steps (the line search of Nader & Guennebaud 2018, "Instant transport maps on 2D grids", ACM TOG
// 37(6), Algorithm 1, plus a fold guard). Also the curved step of a second-order correction (Nocedal &
// Wright, Numerical Optimization, 2nd ed., §15.6).
#pragma once

#include "engine/ot/grid.h"
#include "engine/ot/solver.h"

#include <glm/glm.hpp>

#include <span>

namespace iblx {

struct OtLineStep {
  double t = 0.0;             // 0: no step decreases the merit
  bool guardLimited = false;  // the minimiser lies at (or beyond) the fold guard's bound
};

// The t in [-bound-, bound+] minimising E(t) = sum_c w_c^2 (A_c(P + t G) - m_c)^2, w_c = 1/m_c when
// options.relativeResidual (else 1). The bounds are boundaryFraction of the way to the first t (either sign)
// at which some quad degenerates under options.foldGuard (Area: its signed area reaches 0; Convex: one of
// its corner cross products does; None: no bound), and at most 10 either way. t = 0 unless E decreases by
// more than rounding.
OtLineStep otLineSearch(const OtGrid& grid, const OtMapState& map, std::span<const glm::dvec2> motion,
                        const OtSolverOptions& options);

// The smallest t > 0 at which the signed area of some quad of P + t G reaches 0 (infinity if none does).
double otAreaStepBound(const OtGrid& grid, std::span<const glm::dvec2> positions,
                       std::span<const glm::dvec2> motion);

// a_c = ½ E1 x E2, the quadratic term of every quad's area along G (E1, E2 the motions of its diagonals).
void otQuadraticAreaTerms(const OtGrid& grid, std::span<const glm::dvec2> motion, std::span<double> a);

// Along the curve P + tau G + tau^2 G2 (G2 the motion of the correction d2, J d2 = -a): the longest tau in
// {1, 0.8, 0.64, ...} above t (the straight step's length) at which every quad that has a positive area now
// keeps an area above 1e-3 of its target and the merit (as otLineSearch) is below the straight step's; 0
// when there is none.
double otCurvedStepLength(const OtGrid& grid, const OtMapState& map, std::span<const glm::dvec2> motion,
                          std::span<const glm::dvec2> curveMotion, double t, bool relativeResidual);

}  // namespace iblx
