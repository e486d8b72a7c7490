// The OT map solver of solver.h: the coarse-to-fine levels (transfers in multilevel.h) and, on each
// level, a continuation in the target whose stages are solved by Newton's method (directions in newton.h,
// step lengths in line_search.h). docs/ot_solver.md describes the algorithm in the order it runs.
#include "engine/ot/solver.h"

#include "engine/core/error.h"
#include "engine/ot/geometry.h"
#include "engine/ot/grid.h"
#include "engine/ot/line_search.h"
#include "engine/ot/multilevel.h"
#include "engine/ot/newton.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace iblx {

namespace {

using Vec2 = glm::dvec2;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kFirstStepGoal = 0.5;  // the first Newton step's length a continuation stage is sized for

// One grid level: the continuation in the target, and Newton's method on each of its stages (the iteration
// of Nader & Guennebaud 2018, Algorithm 1, with exact-Jacobian directions).
class LevelSolver {
 public:
  LevelSolver(int n, std::span<const double> rho, const OtSolverOptions& options)
      : grid_(n, options.threads), options_(options), newton_(grid_, options), mass_(rho.size()) {
    const double h2 = 1.0 / (double(n) * n);
    for (std::size_t c = 0; c < rho.size(); ++c) mass_[c] = rho[c] * h2;
    pos_.resize(grid_.vertexCount()), gradDir_.resize(grid_.vertexCount());
    residual_.resize(mass_.size()), dirHat_.resize(mass_.size());
  }

  struct Stats {
    int iterations = 0;
    double l2 = 0.0, l1 = 0.0, linf = 0.0;
    double maxLogError = 0.0;  // max_c |log(A_c / m_c)|
    int stages = 0, undoneStages = 0;
  };

  int factorisations() const { return newton_.factorisations(); }
  bool laplacianFailed() const { return newton_.laplacianFailed(); }
  void setLuFirst() { newton_.setLuFirst(); }
  int krylovSteps() const { return newton_.krylovSteps(); }
  int curvedSteps() const { return curvedStepsTaken_; }

  // Homotopy in the target (a continuation method): the masses go from the starting map's own areas A0 (s =
  // 0, solved by the start) to the target (s = 1) in stages m_s = ((1 - s) A0^p + s m^p)^(1/p)
  // (renormalised), p = homotopyPower. The geometric mean (p = 0) moves every log-area at the same rate; the
  // arithmetic one (p = 1) lets the cells that must grow (the lamps and suns) grow early and the ones that
  // must shrink into slivers shrink late; p = 1/2 is the compromise (docs/ot_solver.md, section 6). Each
  // stage starts from the secant predictor: psi extrapolated along the last two stage solutions, cut back so
  // that every quad keeps boundaryFraction of its area. Easy densities take the single stage s = 1.
  //
  // Step control: the fold guard cuts a stage's first Newton step roughly in proportion to 1 / step, because
  // the distance to the nearest degenerate sliver quad is fixed while the direction grows with the step in s.
  // So a stage abandoned at its first step (shorter than stageMinStep) is retried with its step scaled by t /
  // kFirstStepGoal (at most halved, at least 1/16), and a solved stage scales the next one by its first step
  // over kFirstStepGoal (between 0.5 and 2, at most 1 after more than 4 iterations). A stage that stalls
  // later is retried with half the step. Until a stage is solved, a stage that stalls after it got closer to
  // its target is not undone: the continuation starts again from the map it reached (its s = 0), keeping the
  // unfolding its iterations did. Later stages are undone instead: re-anchoring restarts the secant predictor
  // and the step size.
  //
  // psi must map every quad to a positive area (solveLevels makes sure of it); the guarded line search keeps
  // it so.
  Stats run(std::vector<double>& psi, double targetL2, int maxIterations,
            const std::function<void(int, double)>& progress) {
    grid_.mapOf(psi, pos_);
    const std::vector<double> target = mass_;
    Stats s;
    evaluateResidual(s);
    // The power mean's end points, A0^p and m^p (log A0 and log m for p = 0), computed once per path: they
    // change only when the continuation re-anchors.
    const double p = options_.homotopyPower;
    const auto endPoint = [p](double area) {
      return p == 0.0 ? std::log(area) : std::exp(p * std::log(area));
    };
    std::vector<double> startEnd(target.size()), targetEnd(target.size());
    for (std::size_t c = 0; c < target.size(); ++c) {
      startEnd[c] = endPoint(residual_[c] + target[c]);
      targetEnd[c] = endPoint(target[c]);
    }
    double reached = 0.0, step = 1.0, previous = -1.0;  // previous: the stage solved before `reached`
    std::vector<double> savedPsi, previousPsi;
    std::vector<Vec2> savedPos;
    while (s.iterations < maxIterations) {
      const double next = std::min(1.0, reached + step);
      if (next == 1.0) {
        mass_ = target;
      } else {
        double total = 0.0;
        for (std::size_t c = 0; c < target.size(); ++c) {
          const double mean = (1.0 - next) * startEnd[c] + next * targetEnd[c];
          total += mass_[c] = p == 0.0 ? std::exp(mean) : std::pow(mean, 1.0 / p);
        }
        for (double& m : mass_) m /= total;
      }
      savedPsi = psi, savedPos = pos_;
      if (previous >= 0.0) predict(psi, previousPsi, (next - reached) / (reached - previous));
      const bool last = next == 1.0;
      const int budget = last ? maxIterations - s.iterations
                              : std::min(options_.stageIterations, maxIterations - s.iterations);
      // Damped Newton far from a stage's solution crawls (guarded steps of a few percent), so a stage whose
      // step falls below stageMinStep is abandoned for a smaller one; the smallest stages run
      // unconditionally.
      const bool strict = step > options_.minStageStep;
      const int before = s.iterations;
      ++s.stages;
      double firstStep = 1.0;
      const bool ok = iterate(psi, s, last ? targetL2 : -1.0, budget,
                              last ? progress : std::function<void(int, double)>{}, strict, firstStep);
      if (ok) {
        previous = reached, previousPsi = savedPsi;
        reached = next;
        if (last) break;
        double factor = std::clamp(firstStep / kFirstStepGoal, 0.5, 2.0);
        if (s.iterations - before > 4) factor = std::min(factor, 1.0);
        step = std::min(1.0, step * factor);
        continue;
      }
      if (step <= options_.minStageStep) break;  // keep the best map reached
      if (reached == 0.0 && s.iterations > before && s.l2 < stageStartL2_) {
        // No stage solved yet, and this one got closer to its target before it crawled: the continuation
        // starts again from the map reached.
        for (std::size_t c = 0; c < target.size(); ++c) startEnd[c] = endPoint(residual_[c] + mass_[c]);
      } else {
        psi = savedPsi, pos_ = savedPos;  // undo the stage and take a smaller one
      }
      step = otRetriedStageStep(reached, next, firstStep,
                                s.iterations == before && firstStep < options_.stageMinStep, options_);
      ++s.undoneStages;
      curvedSteps_ = options_.secondOrderCorrection;
    }
    mass_ = target;
    evaluateResidual(s);
    return s;
  }

  // Secant predictor of a continuation stage: psi += tau * ratio * (psi - previousPsi), previousPsi the
  // solution of the stage before psi's. tau <= 1 keeps every quad's area positive with the line search's
  // margin, so the guarded iteration can start from it (the full extrapolation folds quads next to suns).
  // dirHat_ and gradDir_ serve as scratch: iterate() recomputes both before using them.
  double predict(std::vector<double>& psi, std::span<const double> previousPsi, double ratio) {
    for (std::size_t c = 0; c < psi.size(); ++c) dirHat_[c] = ratio * (psi[c] - previousPsi[c]);
    grid_.gradient(dirHat_, gradDir_);
    const double tau = std::min(1.0, options_.boundaryFraction * otAreaStepBound(grid_, pos_, gradDir_));
    for (std::size_t c = 0; c < psi.size(); ++c) psi[c] += tau * dirHat_[c];
    for (std::size_t v = 0; v < pos_.size(); ++v) pos_[v] += tau * gradDir_[v];
    return tau;
  }

  // psi = tau * toward with the largest tau <= 1 that keeps every quad boundaryFraction of the way from the
  // identity to degenerate (predict() from the identity): the start of a level whose prolonged potential
  // still folds quads after maxSmoothingPasses. Returns tau.
  double startToward(std::span<const double> toward, std::vector<double>& psi) {
    std::vector<double> negated(toward.size());
    for (std::size_t c = 0; c < toward.size(); ++c) negated[c] = -toward[c];
    std::fill(psi.begin(), psi.end(), 0.0);
    foldedAt(psi);  // pos_ = the identity grid
    return predict(psi, negated, 1.0);
  }

  // Newton's method on the current stage until E <= targetL2 and L1 <= targetL1 (or, for targetL2 < 0, an
  // intermediate stage's max |log(A / m)| <= stageLogError): true; or a stall or the budget: false.
  // s.iterations counts every iteration.
  bool iterate(std::vector<double>& psi, Stats& s, double targetL2, int budget,
               const std::function<void(int, double)>& progress, bool strict, double& firstStep) {
    constexpr double kCurveBelow = 0.9;  // curvedStep() for guarded steps shorter than this
    evaluateResidual(s);
    stageStartL2_ = s.l2;
    rhs_.resize(residual_.size());
    for (int k = 0;; ++k) {
      if (targetL2 < 0.0 ? s.maxLogError <= options_.stageLogError
                         : (s.l2 <= targetL2 && s.l1 <= options_.targetL1))
        return true;
      if (k >= budget) return false;
      // 1. Newton direction: J d = -r, J the exact Jacobian of the areas at the current map.
      for (std::size_t c = 0; c < rhs_.size(); ++c) rhs_[c] = -residual_[c];
      newton_.direction(state(), rhs_, dirHat_);
      grid_.gradient(dirHat_, gradDir_);
      // 2. Its length, exact along the line; a step the fold guard cut short follows the curved path instead,
      //    once this level has needed to undo a continuation stage (curvedSteps_).
      const OtLineStep line = otLineSearch(grid_, state(), gradDir_, options_);
      double t = line.t;
      const double curved =
          curvedSteps_ && line.guardLimited && t > 0.0 && t < kCurveBelow ? curvedStep(t) : 0.0;
      if (curved > 0.0) t = curved, ++curvedStepsTaken_;
      if (k == 0) firstStep = std::abs(t);
      if (t == 0.0) return false;  // stalled
      if (strict && std::abs(t) < options_.stageMinStep) return false;
      // 3. Step: psi += t d (+ t^2 d2 on a curved step); the vertices move by the gradient of that.
      for (std::size_t c = 0; c < psi.size(); ++c)
        psi[c] += t * dirHat_[c] + (curved > 0.0 ? t * t * curveDir_[c] : 0.0);
      for (std::size_t v = 0; v < pos_.size(); ++v)
        pos_[v] += t * gradDir_[v] + (curved > 0.0 ? t * t * curveGrad_[v] : Vec2(0.0));
      ++s.iterations;
      evaluateResidual(s);  // recomputed from the vertices, not updated, so rounding cannot drift
      if (progress) progress(s.iterations, s.l2);
    }
  }

  // Second-order correction of a step that the fold guard cut to t (Nocedal & Wright, Numerical Optimization,
  // 2nd ed., §15.6): along psi + tau d the areas are A + tau b + tau^2 a, b = J d = -r, so near a sun the
  // quadratic term a(d) = ½ e1 x e2 drives sliver quads through zero long before the Newton step's end.
  // With J d2 = -a(d), the curve psi + tau d + tau^2 d2 has areas A - tau r + O(tau^3). d2 comes from one
  // solve with the current factors (OtNewtonSystem::correction): it need not be exact, because the curve is
  // taken only when it beats the straight step. Returns the curve's step (otCurvedStepLength), or 0.
  double curvedStep(double t) {
    otQuadraticAreaTerms(grid_, gradDir_, rhs_);  // rhs_ is free once the direction is solved
    curveDir_.resize(residual_.size()), curveGrad_.resize(pos_.size());
    newton_.correction(rhs_, curveDir_);
    grid_.gradient(curveDir_, curveGrad_);
    return otCurvedStepLength(grid_, state(), gradDir_, curveGrad_, t, options_.relativeResidual);
  }

  const std::vector<Vec2>& positions() const { return pos_; }

  // The quads that the map of psi folds, which a start must not have: those of area <= 0 (under the Convex
  // guard, those not strictly convex). Leaves that map in pos_.
  int foldedAt(std::span<const double> psi) {
    grid_.mapOf(psi, pos_);
    if (options_.foldGuard == OtFoldGuard::Convex) return otFoldedQuads(pos_, grid_.n());
    const std::vector<double> areas = otQuadAreas(pos_, grid_.n());
    return int(std::count_if(areas.begin(), areas.end(), [](double a) { return !(a > 0.0); }));
  }

 private:
  OtMapState state() const { return {pos_, mass_, residual_}; }

  // residual_ = A - m at pos_, and the stage's error measures.
  void evaluateResidual(Stats& s) {
    const int n = grid_.n();
    const auto sums = otReduceChunks<4>(
        grid_.threads(), n, 8,
        [&](int lo, int hi) {
          std::array<double, 4> acc{0.0, 0.0, 0.0, 0.0};
          for (int j = lo; j < hi; ++j)
            for (int i = 0; i < n; ++i) {
              const auto [p00, p10, p11, p01] = grid_.quad(i, j);
              const double area = 0.5 * cross2(pos_[p11] - pos_[p00], pos_[p01] - pos_[p10]);
              const std::size_t c = grid_.cell(i, j);
              const double r = area - mass_[c];
              residual_[c] = r;
              acc[0] += r * r, acc[1] += std::abs(r), acc[2] = std::max(acc[2], std::abs(r));
              acc[3] = std::max(acc[3], area > 0.0 ? std::abs(std::log(area / mass_[c])) : kInf);
            }
          return acc;
        },
        {false, false, true, true});
    const double cells = double(n) * n;
    s.l2 = sums[0] * cells, s.l1 = sums[1], s.linf = sums[2] * cells, s.maxLogError = sums[3];
  }

  OtGrid grid_;  // before newton_, which refers to it
  const OtSolverOptions& options_;
  OtNewtonSystem newton_;
  std::vector<double> mass_, residual_;  // the current stage's target areas m and A - m
  std::vector<Vec2> pos_;                // the map: (n+1)^2 vertex positions
  std::vector<double> rhs_, dirHat_;     // the Newton system's right-hand side -r, and its solution d
  std::vector<Vec2> gradDir_;            // the vertex motion of d
  std::vector<double> curveDir_;         // d2 of a curved step ...
  std::vector<Vec2> curveGrad_;          // ... and its vertex motion
  bool curvedSteps_ = false;             // curvedStep() is in use on this level
  double stageStartL2_ = 0.0;            // E when the last iterate() started, against that stage's target
  int curvedStepsTaken_ = 0;
};

struct LevelResult {
  std::vector<double> psi;
  std::vector<Vec2> positions;
  LevelSolver::Stats stats;
  int coarseIterations = 0;
  bool laplacianFailed = false;      // the level ended with LU-preconditioned directions
  std::vector<OtLevelStats> levels;  // coarsest first
};

LevelResult solveLevels(std::span<const double> rho, int n, const OtSolverOptions& options, bool finest) {
  LevelResult result;
  if (options.coarseToFine && n % 2 == 0 && n / 2 >= std::max(options.coarsestSize, 2)) {
    const std::vector<double> coarse = otRestrictDensity(rho, n);
    LevelResult c = solveLevels(coarse, n / 2, options, false);
    result.coarseIterations = c.coarseIterations + c.stats.iterations;
    result.psi = otProlongPotential(c.psi, n / 2);
    result.laplacianFailed = c.laplacianFailed;
    result.levels = std::move(c.levels);
  } else {
    result.psi.assign(std::size_t(n) * n, 0.0);
  }
  const auto start = std::chrono::steady_clock::now();
  OtLevelStats level;
  level.n = n;
  LevelSolver solver(n, rho, options);
  // A level whose coarser one ended with LU-preconditioned directions starts with them: the Laplacian's
  // GMRES would most likely fail here too.
  if (result.laplacianFailed) solver.setLuFirst();
  const double target = finest ? options.targetL2 : std::max(options.targetL2, options.coarseTargetL2);
  const std::function<void(int, double)> progress = finest ? options.progress : nullptr;
  // The converged coarse map has non-convex quads wherever it compresses strongly (next to suns and lamps),
  // and the prolonged potential folds fine quads there. Smoothing the whole potential unfolds them and keeps
  // the coarse-scale transport (multilevel.h); smoothing only near the folded quads folds new ones at the
  // edge of the smoothed region.
  level.startFoldedQuads = solver.foldedAt(result.psi);
  if (level.foldedStart()) {
    const auto folded = [&solver](std::span<const double> psi) { return solver.foldedAt(psi); };
    if (otSmoothUntilUnfolded(result.psi, n, options.maxSmoothingPasses, folded, level.smoothingPasses) > 0) {
      const std::vector<double> smoothed = result.psi;
      level.restartScale = solver.startToward(smoothed, result.psi);
    }
  }
  result.stats = solver.run(result.psi, target, options.maxIterations, progress);
  if (finest) result.positions = solver.positions();
  result.laplacianFailed = solver.laplacianFailed();
  level.iterations = result.stats.iterations, level.stages = result.stats.stages;
  level.undoneStages = result.stats.undoneStages, level.factorisations = solver.factorisations();
  level.krylovSteps = solver.krylovSteps(), level.curvedSteps = solver.curvedSteps();
  level.l2 = result.stats.l2;
  level.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.levels.push_back(level);
  return result;
}

}  // namespace

double otRetriedStageStep(double reached, double next, double firstStep, bool abandonedAtFirstStep,
                          const OtSolverOptions& options) {
  // Scaled from the step actually attempted, not the nominal one: a stage clipped at s = 1 (reached + step >
  // 1) and retried with half the nominal step could land on s = 1 again and repeat the failed stage exactly.
  const double attempted = next - reached;
  const double factor = abandonedAtFirstStep ? std::clamp(firstStep / kFirstStepGoal, 1.0 / 16.0, 0.5) : 0.5;
  return std::max(options.minStageStep, attempted * factor);
}

std::string otLevelStartNote(const OtLevelStats& level) {
  if (!level.foldedStart()) return "";
  const std::string folded = "folded start (" + std::to_string(level.startFoldedQuads) + " quads), ";
  if (level.restartScale > 0.0) return folded + "restarted at " + std::to_string(level.restartScale);
  return folded + std::to_string(level.smoothingPasses) +
         (level.smoothingPasses == 1 ? " smoothing pass" : " smoothing passes");
}

std::vector<double> otQuadAreas(std::span<const glm::dvec2> vertices, int n) {
  IBLX_ASSERT(vertices.size() == std::size_t(n + 1) * (n + 1));
  std::vector<double> areas(std::size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::size_t p00 = std::size_t(j) * (n + 1) + i, p10 = p00 + 1, p01 = p00 + n + 1, p11 = p01 + 1;
      areas[std::size_t(j) * n + i] =
          0.5 * cross2(vertices[p11] - vertices[p00], vertices[p01] - vertices[p10]);
    }
  return areas;
}

int otFoldedQuads(std::span<const glm::dvec2> vertices, int n) {
  IBLX_ASSERT(vertices.size() == std::size_t(n + 1) * (n + 1));
  int folded = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::size_t p00 = std::size_t(j) * (n + 1) + i, p10 = p00 + 1, p01 = p00 + n + 1, p11 = p01 + 1;
      folded += strictlyConvexQuad(vertices[p00], vertices[p10], vertices[p11], vertices[p01]) ? 0 : 1;
    }
  return folded;
}

OtMap solveOtMap(std::span<const double> density, int n, const OtSolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (n < 1 || density.size() != std::size_t(n) * n)
    throw Error("OT solver: the density has " + std::to_string(density.size()) +
                " values, expected n^2 = " + std::to_string(std::max(n, 0)) + "^2");
  // Between the geometric (0) and the arithmetic (1) mean; beyond 1, m^p of the smallest cells underflows.
  if (!(options.homotopyPower >= 0.0 && options.homotopyPower <= 1.0))
    throw Error("OT solver: homotopyPower must be in [0, 1], got " + std::to_string(options.homotopyPower));
  if (options.krylovSteps < 1)
    throw Error("OT solver: krylovSteps must be at least 1, got " + std::to_string(options.krylovSteps));
  double sum = 0.0;
  for (double v : density) {
    if (!std::isfinite(v) || v < 0.0)
      throw Error("OT solver: the density has a negative or non-finite value");
    sum += v;
  }
  if (!(sum > 0.0)) throw Error("OT solver: the density is zero everywhere");
  // Floor at eps * mean, then back to mean 1 (see the header).
  const double cells = double(n) * n, mean = sum / cells, floorValue = options.floorFraction * mean;
  std::vector<double> rho(density.begin(), density.end());
  double floored = 0.0;
  for (double& v : rho) floored += (v = std::max(v, floorValue));
  for (double& v : rho) v *= cells / floored;

  LevelResult levels = solveLevels(rho, n, options, true);
  OtMap map;
  map.n = n;
  map.vertices = std::move(levels.positions);
  map.density = std::move(rho);
  map.psi = std::move(levels.psi);
  map.iterations = levels.stats.iterations;
  map.coarseIterations = levels.coarseIterations;
  map.levels = std::move(levels.levels);
  // Final metrics from the returned vertices, independently of the iteration's bookkeeping.
  const std::vector<double> areas = otQuadAreas(map.vertices, n);
  for (std::size_t c = 0; c < areas.size(); ++c) {
    const double r = areas[c] - map.density[c] / cells;
    map.negativeAreaQuads += areas[c] <= 0.0 ? 1 : 0;
    map.l2 += r * r * cells, map.l1 += std::abs(r), map.linf = std::max(map.linf, std::abs(r) * cells);
  }
  map.foldedQuads = otFoldedQuads(map.vertices, n);
  map.converged = map.l2 <= options.targetL2 && map.l1 <= options.targetL1;
  map.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return map;
}

}  // namespace iblx
