// Optimal-transport map from an environment's sampling density on an n x n grid over the lat-long square to
// the uniform density on [0,1]^2, after Nader & Guennebaud, "Instant Transport Maps on 2D Grids" (ACM TOG
// 37(6), 2018, §4-5 and Algorithm 1). CPU, double precision; the samplers build on the map. docs/ot_solver.md
// describes the algorithm and its figures.
//
// Differences from that paper's released solver (written from the notes, not its code):
// - Newton directions on the relative residual (A - m) / m (newton.h): GMRES preconditioned by the fixed
//   pseudo-Laplacian L (the exact area Jacobian at the identity, diagonal in the DCT-II basis, O(n^2 log n)
//   per solve; the paper's chord direction -L^-1 r is its first Krylov vector) while that reaches its
//   tolerance, else by LU factors of the exact Jacobian at an earlier map (grid_lu.h: nested dissection,
//   multifrontal, factored in single precision), renewed at the current map only when GMRES with them needs
//   more than a few steps;
// - a line search that keeps every quad's signed area positive (OtFoldGuard::Area, line_search.h), going
//   at most boundaryFraction of the way to the first degenerate quad;
// - continuation: the target is approached in stages m_s = ((1-s) A0^(1/2) + s m^(1/2))^2 (renormalised) from
//   the start map's own areas A0; each stage starts from a secant predictor (cut back to keep every quad's
//   area positive); a stage whose Newton step falls below stageMinStep is undone (or, before any stage is
//   solved, kept as the new start when it got closer to its target) and retried with a smaller step in s,
//   sized from how far its first Newton step got (see LevelSolver::run). Easy densities take the single stage
//   s = 1;
// - on a level that had to undo a stage, steps cut short by the fold guard follow a second-order correction
//   (a curve on which the quadratic area term is cancelled; LevelSolver::curvedStep);
// - coarse-to-fine (multilevel.h): the density is box-restricted to n/2, n/4, ..., solved there and psi is
//   prolonged (averaged at the coarse vertices, then bilinear); where a prolonged start folds quads (next to
//   suns and lamps, in strongly compressed regions), psi is smoothed by binomial passes until it does not (at
//   most maxSmoothingPasses, else the level starts part of the way from the identity towards it); a level
//   whose coarser one needed LU-preconditioned directions starts with them;
// - a density floor: rho' = max(rho, floorFraction * mean(rho)), renormalised to mean 1. Zero regions then
//   collapse to thin quads instead of folding. The samplers' pdfs stay exact because they come from the map.
//   The default eps = 1e-2 costs a sampler at most a factor 1 + eps in the second moment of f / p (the
//   floored pdf is >= p / (1 + eps) wherever p > 0), and it bounds the contrast between a sun's cells and the
//   near-empty cells that must become slivers beside them, which sets how long the solver crawls there.
// The converged map can hold self-intersecting quads of positive area next to a sun; the samplers solve for
// a map with their suns split off (engine/sampling/env/env_ot_sun.h) and map.h untangles what twists remain.
#pragma once

#include "engine/ot/density.h"

#include <glm/glm.hpp>

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace iblx {

// What the line search keeps valid. Convex: every quad stays strictly convex (its bilinear map has a positive
// Jacobian everywhere). Area: every quad keeps a positive signed area (it may become non-convex). None:
// otmap's unconstrained search.
enum class OtFoldGuard { None, Area, Convex };

struct OtSolverOptions {
  int maxIterations = 2000;  // at the finest level; each coarse level gets the same cap
  double targetL2 = 1e-7;    // E = sum_c h^2 (rho_achieved - rho)^2, mean-1 units (Nader & Guennebaud 2018)
  double targetL1 = 1e-3;    // sum_c |A_c - h^2 rho_c|, the mass error (2 x total variation)
  double floorFraction = 1e-2;   // density floor eps: rho' = max(rho, eps * mean), renormalised
  bool coarseToFine = true;      // solve on n/2 first (recursively) and prolong psi
  int coarsestSize = 16;         // no level below this size
  double coarseTargetL2 = 1e-5;  // looser target on the coarse levels: the fine level corrects them
  int krylovSteps = 20;          // inexact Newton directions: GMRES(krylovSteps) on the exact Jacobian, >= 1
  double krylovTolerance = 0.1;  // GMRES stops at ||r + J d|| <= krylovTolerance ||r||
  int stageIterations = 60;      // continuation: iteration budget of an intermediate stage
  double stageLogError = 0.05;   // continuation: an intermediate stage is solved to max |log(A / m)| <= this
  double minStageStep = 1e-3;    // continuation: give up below this step in s
  double stageMinStep = 0.25;    // continuation: a Newton step shorter than this abandons the stage
  // continuation: the stage targets are the power mean m_s = ((1 - s) A0^p + s m^p)^(1/p) of the start's
  // areas and the target (renormalised), p in [0, 1]; p = 0 is the geometric mean A0^(1 - s) m^s. See
  // LevelSolver::run.
  double homotopyPower = 0.5;
  // coarse-to-fine: a prolonged potential that folds quads is smoothed by 1, 2, 4, ... binomial passes until
  // none is folded (solveLevels in solver.cpp); past this many passes the level starts instead as far from
  // the identity towards the smoothed potential as every quad stays unfolded. 0 (or less): always the latter.
  int maxSmoothingPasses = 1024;
  // Once a level has had to undo a continuation stage, a step that the fold guard cuts short follows the
  // curve psi + t d + t^2 d2 with J d2 = -(the quadratic area term along d) (LevelSolver::curvedStep). Only
  // then: on maps that need no such retreat, the longer steps make the lagged LU factors go stale sooner, for
  // no fewer iterations (docs/ot_solver.md, "Tried and dropped").
  bool secondOrderCorrection = true;
  OtFoldGuard foldGuard = OtFoldGuard::Area;
  // Newton directions and the L2 line search on relative residuals (A - m) / m: GMRES rows and merit terms
  // weighted by 1/m, so the sun's cells cannot hide a 100% error on a sky cell.
  bool relativeResidual = true;
  double boundaryFraction = 0.9;  // a step goes at most this fraction of the way to the first degenerate quad
  int threads = 0;                // 0 = hardware concurrency
  std::function<void(int, double)> progress;  // (iteration at the finest level, E) after every iteration
};

// The continuation's next step in s after the stage from `reached` to `next` failed (LevelSolver::run): the
// step attempted, next - reached, times firstStep / 0.5 within [1/16, 1/2] when the stage was abandoned at
// its first Newton step (shorter than stageMinStep), else times 1/2; at least minStageStep.
double otRetriedStageStep(double reached, double next, double firstStep, bool abandonedAtFirstStep,
                          const OtSolverOptions& options);

// Bumped whenever the solver's results or the options hashed into the cache key change, so that cached maps
// (cache.h) are re-solved.
inline constexpr int kOtSolverVersion = 13;

// What one grid level of the coarse-to-fine solve did (coarsest first in OtMap::levels).
struct OtLevelStats {
  int n = 0;
  int iterations = 0;      // Newton iterations (line searches that moved)
  int stages = 0;          // continuation stages attempted (1 for an easy density)
  int undoneStages = 0;    // stages undone (or, before any was solved, re-anchored) and retried smaller
  int factorisations = 0;  // sparse LU factorisations of the exact Jacobian
  int krylovSteps = 0;     // GMRES steps, each one preconditioner solve and one Jacobian product
  int curvedSteps = 0;     // steps along a second-order correction (OtSolverOptions::secondOrderCorrection)
  // Quads that the prolonged coarse map folded here (area <= 0; not strictly convex under
  // OtFoldGuard::Convex), 0 for an unfolded start ...
  int startFoldedQuads = 0;
  int smoothingPasses = 0;    // ... which psi was then smoothed by this many binomial passes to unfold
  double restartScale = 0.0;  // > 0: that did not unfold it, and the level started this fraction of the way
                              // from the identity towards the smoothed potential
  double seconds = 0.0;       // wall time of the level
  double l2 = 0.0;            // E reached at this level

  bool foldedStart() const { return startFoldedQuads > 0; }
};

// How a level started, for reports: "" from an unfolded prolonged map, else "folded start (N quads), P
// smoothing passes" or "folded start (N quads), restarted at TAU" (OtLevelStats::restartScale).
std::string otLevelStartNote(const OtLevelStats& level);

struct OtMap {
  int n = 0;
  // (n+1)^2 vertices, row-major j*(n+1)+i: where grid vertex (i/n, j/n) of the density square maps to in the
  // uniform square. Cell c's quad (vertices (i,j), (i+1,j), (i+1,j+1), (i,j+1)) has area h^2 rho_c at
  // convergence, with rho the floored, mean-1 density (`density`).
  std::vector<glm::dvec2> vertices;
  std::vector<double> density;       // the floored, mean-1 target the map was solved for (n^2)
  std::vector<double> psi;           // the potential, one value per cell (n^2), mean 0
  int iterations = 0;                // at the finest level
  int coarseIterations = 0;          // summed over the coarse levels
  std::vector<OtLevelStats> levels;  // coarsest first, the finest (n) last; empty when read from the cache
  double seconds = 0.0;              // wall time of the whole solve, coarse levels included
  double l2 = 0.0;                   // E = sum_c h^2 (A_c/h^2 - rho_c)^2
  double l1 = 0.0;                   // sum_c |A_c - h^2 rho_c|
  double linf = 0.0;                 // max_c |A_c - h^2 rho_c| / h^2
  // Quads whose bilinear map does not have a strictly positive Jacobian everywhere: the Jacobian determinant
  // of a bilinear patch is affine in each parameter, so this is "some corner cross product (P_next - P) x
  // (P_prev - P), taken counter-clockwise, is <= 0". Negative areas and self-intersecting or non-convex quads
  // are all counted.
  int foldedQuads = 0;
  // The subset with signed area <= 0 ("folded": the reference solver's count).
  int negativeAreaQuads = 0;
  bool converged = false;  // l2 <= targetL2 and l1 <= targetL1
};

// Signed quad areas ½ (P11 - P00) x (P01 - P10) of a vertex grid (n+1)^2 -> n^2 (Nader & Guennebaud 2018).
std::vector<double> otQuadAreas(std::span<const glm::dvec2> vertices, int n);
// foldedQuads as defined in OtMap.
int otFoldedQuads(std::span<const glm::dvec2> vertices, int n);

// Solves for the map of `density` (n x n, row-major, >= 0, finite, not all zero; any scale).
// Throws iblx::Error on bad input. Returns the best map reached even when it did not converge.
OtMap solveOtMap(std::span<const double> density, int n, const OtSolverOptions& options = {});

}  // namespace iblx
