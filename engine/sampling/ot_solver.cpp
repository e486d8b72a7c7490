// The OT map solver of ot_solver.h: density from an environment, coarse-to-fine levels, and per level a
// continuation in the target with Newton-GMRES directions and a fold-guarded line search.
#include "engine/sampling/ot_solver.h"

#include "engine/core/error.h"
#include "engine/sampling/grid_lu.h"
#include "engine/sampling/latlong_texel.h"
#include "engine/sampling/ot_dct.h"
#include "engine/sampling/ot_geometry.h"
#include "engine/core/sphere_mapping.h"

#include <algorithm>
#include <array>

#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <cstdio>
#include <cstdlib>

namespace iblx {

namespace {

using Vec2 = glm::dvec2;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kFirstStepGoal = 0.5;  // the first Newton step's length a continuation stage is sized for

// Deterministic parallel reduction: fn(lo, hi) -> K partial sums/maxima, combined in chunk order.
template <int K, typename F>
std::array<double, K> reduceChunks(int threads, int count, int minChunk, F fn,
                                   std::array<bool, K> isMax = {}) {
  std::mutex mutex;
  std::vector<std::pair<int, std::array<double, K>>> parts;
  parallelChunks(threads, count, minChunk, [&](int lo, int hi) {
    const std::array<double, K> p = fn(lo, hi);
    const std::lock_guard lock(mutex);
    parts.emplace_back(lo, p);
  });
  std::sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::array<double, K> total{};
  for (int k = 0; k < K; ++k)
    if (isMax[std::size_t(k)]) total[std::size_t(k)] = -kInf;
  for (const auto& [lo, p] : parts)
    for (std::size_t k = 0; k < K; ++k) total[k] = isMax[k] ? std::max(total[k], p[k]) : total[k] + p[k];
  return total;
}

// Smallest t > 0 with c0 + c1 t + c2 t^2 = 0, for c0 > 0 (infinity if the quadratic stays positive).
double firstPositiveRoot(double c0, double c1, double c2) {
  if (c2 == 0.0) return c1 < 0.0 ? -c0 / c1 : kInf;
  const double disc = c1 * c1 - 4.0 * c2 * c0;
  if (disc < 0.0) return kInf;
  const double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));  // stable roots q/c2 and c0/q
  double best = kInf;
  for (double r : {q / c2, q != 0.0 ? c0 / q : kInf})
    if (r > 0.0) best = std::min(best, r);
  return best;
}

// Quartic E(t) = sum_k e[k] t^k and its derivatives.
struct Quartic {
  std::array<double, 5> e{};
  double value(double t) const { return (((e[4] * t + e[3]) * t + e[2]) * t + e[1]) * t + e[0]; }
  double slope(double t) const { return ((4.0 * e[4] * t + 3.0 * e[3]) * t + 2.0 * e[2]) * t + e[1]; }
};

// argmin of E on [lo, hi] (lo <= 0 <= hi): E'' (a quadratic) splits the interval into pieces where E' is
// monotone; each sign change of E' is bisected. Exact up to rounding, no cubic formula (the line search of Nader & Guennebaud 2018, Algorithm 1
// uses companion-matrix eigenvalues instead).
double minimiseQuartic(const Quartic& q, double lo, double hi) {
  std::vector<double> cuts{lo, hi};
  const double a = 12.0 * q.e[4], b = 6.0 * q.e[3], c = 2.0 * q.e[2];
  if (a != 0.0) {
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      const double s = -0.5 * (b + std::copysign(std::sqrt(disc), b));
      cuts.push_back(s / a);
      if (s != 0.0) cuts.push_back(c / s);
    }
  } else if (b != 0.0) {
    cuts.push_back(-c / b);
  }
  std::erase_if(cuts, [&](double t) { return !(t >= lo && t <= hi); });
  std::sort(cuts.begin(), cuts.end());
  double bestT = 0.0, bestE = q.value(0.0);
  const auto consider = [&](double t) {
    const double v = q.value(t);
    if (v < bestE) bestE = v, bestT = t;
  };
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    consider(cuts[i]);
    if (i + 1 == cuts.size()) break;
    double l = cuts[i], r = cuts[i + 1];
    double sl = q.slope(l);
    if ((sl > 0.0) == (q.slope(r) > 0.0)) continue;
    for (int it = 0; it < 100 && r - l > 1e-15 * std::max(1.0, std::abs(l)); ++it) {
      const double m = 0.5 * (l + r), sm = q.slope(m);
      if ((sm > 0.0) == (sl > 0.0))
        l = m, sl = sm;
      else
        r = m;
    }
    consider(0.5 * (l + r));
  }
  return bestT;
}

// One grid level: the fixed pseudo-Laplacian's DCT solver and the iteration of Nader & Guennebaud 2018, Algorithm 1.
class LevelSolver {
 public:
  LevelSolver(int n, std::span<const double> rho, const OtSolverOptions& options)
      : n_(n), v_(n + 1), threads_(options.threads), options_(options), dct_(n), mass_(rho.size()) {
    const double h2 = 1.0 / (double(n) * n);
    for (std::size_t c = 0; c < rho.size(); ++c) mass_[c] = rho[c] * h2;
    // Eigenvalues of -L = 2 (I - A (x) A), A the clamped 1-D average with eigenvalues cos(pi k / n) (DCT-II).
    inverseEigen_.resize(std::size_t(n) * n);
    for (int k = 0; k < n; ++k)
      for (int l = 0; l < n; ++l) {
        const double lambda = 2.0 * (1.0 - std::cos(kPi * k / n) * std::cos(kPi * l / n));
        inverseEigen_[std::size_t(k) * n + l] = (k == 0 && l == 0) ? 0.0 : 1.0 / lambda;  // mean of d is 0
      }
    const std::size_t nv = std::size_t(v_) * v_;
    pos_.resize(nv), gradDir_.resize(nv);
    residual_.resize(mass_.size()), dirHat_.resize(mass_.size());
    pad_.resize(std::size_t(n + 2) * (n + 2));
  }

  struct Stats {
    int iterations = 0;
    double l2 = 0.0, l1 = 0.0, linf = 0.0;
    double maxLogError = 0.0;  // max_c |log(A_c / m_c)|
    int stages = 0, undoneStages = 0;
  };

  int factorisations() const { return factorisations_; }
  // True once the Laplacian-preconditioned GMRES missed its tolerance on this level (the map is too distorted
  // for it); the next level starts with LU directions when the coarse one ended that way (setLuFirst),
  // which spares it a failing GMRES(krylovSteps) of DCT solves (0.2 s at n = 512, 1 s at n = 1024).
  bool laplacianFailed() const { return laplacianFailed_; }
  void setLuFirst() { laplacianFailed_ = true; }
  int krylovSteps() const { return krylovSteps_; }
  int curvedSteps() const { return curvedStepsTaken_; }

  // Homotopy in the target (a continuation method): the masses go from the starting map's own areas A0 (s =
  // 0, solved by the start) to the target (s = 1) in stages m_s = ((1 - s) A0^p + s m^p)^(1/p)
  // (renormalised), p = homotopyPower. The geometric mean (p = 0) moves every log-area at the same rate; the
  // arithmetic one (p = 1) lets the cells that must grow (the lamps and suns) grow early and the ones that
  // must shrink into slivers shrink late. Measured (iblx_ot_bench, alternating): p = 1/2 took sunrise,
  // interior and night at n = 1024 from 25.4, 27.4, 29.3 s to 8.8, 18.9, 14.8 s and at 512
  // from 1.8-2.1, 3.5, 4.2-4.4 s to 1.7-1.8, 3.2, 3.0-3.2 s, the other maps within the noise; p = 1 made
  // night at 512 2.2 s but interior 4.1 s, p = 1/4 was between p = 0 and 1/2. Each stage starts from the
  // secant predictor: psi extrapolated along the last two stage solutions, cut back so that every quad keeps
  // boundaryFraction of its area. Easy densities take the single stage s = 1.
  //
  // Step control: the fold guard cuts a stage's first Newton step roughly in proportion to 1 / step, because
  // the distance to the nearest degenerate sliver quad is fixed while the direction grows with the step in s
  // (measured on sunrise at n = 512: t * step stayed within 0.025-0.045 for steps 0.06-0.5). So a stage
  // abandoned at its first step (shorter than stageMinStep) is retried with its step scaled by t /
  // kFirstStepGoal (at most halved, at least 1/16), and a solved stage scales the next one by its first step
  // over kFirstStepGoal (between 0.5 and 2, at most 1 after more than 4 iterations). A stage that stalls
  // later is retried with half the step. Measured at n = 512 against plain halving and doubling: sunrise from
  // 36 stages to 21 and 17.6 s to 15.8 s, the other maps within the noise. Until a stage is solved, a stage
  // that stalls after it got closer to its target is not undone: the continuation starts again from the map
  // it reached (its s = 0). Re-anchoring after later stages too made sunrise at 512 take 47 stages (the
  // secant predictor and the step size start over each time).
  //
  // psi must map every quad to a positive area (solveLevels makes sure of it); the guarded line search keeps
  // it so.
  Stats run(std::vector<double>& psi, double targetL2, int maxIterations,
            const std::function<void(int, double)>& progress) {
    const int n = n_;
    gradient(psi, pos_);
    for (int j = 0; j < v_; ++j)
      for (int i = 0; i < v_; ++i) pos_[vi(i, j)] += Vec2(double(i) / n, double(j) / n);
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
        // starts again from the map reached (undoing it threw away up to 6 Newton iterations of unfolding on
        // sunrise and city).
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
  // margin, so the guarded iteration can start from it (the full extrapolation folded quads next to suns in
  // most stages). Measured: 20-50 % fewer Newton directions at n = 256 and 512. dirHat_ and gradDir_ serve as
  // scratch: iterate() recomputes both before using them.
  double predict(std::vector<double>& psi, std::span<const double> previousPsi, double ratio) {
    const int n = n_;
    for (std::size_t c = 0; c < psi.size(); ++c) dirHat_[c] = ratio * (psi[c] - previousPsi[c]);
    gradient(dirHat_, gradDir_);
    const double limit = reduceChunks<1>(
        threads_, n, 8,
        [&](int lo, int hi) {
          double t = kInf;
          for (int j = lo; j < hi; ++j)
            for (int i = 0; i < n; ++i) {
              const std::size_t p00 = vi(i, j), p10 = p00 + 1, p01 = p00 + v_, p11 = p01 + 1;
              const Vec2 d1 = pos_[p11] - pos_[p00], d2 = pos_[p01] - pos_[p10];
              const Vec2 e1 = gradDir_[p11] - gradDir_[p00], e2 = gradDir_[p01] - gradDir_[p10];
              t = std::min(t, firstPositiveRoot(0.5 * cross2(d1, d2), 0.5 * (cross2(d1, e2) + cross2(e1, d2)),
                                                0.5 * cross2(e1, e2)));
            }
          return std::array<double, 1>{-t};
        },
        {true})[0];
    const double tau = std::min(1.0, options_.boundaryFraction * -limit);
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

  // The iteration of Nader & Guennebaud 2018 (Algorithm 1) until E <= targetL2 and L1 <= targetL1 (true), or a stall or the budget
  // (false). s.iterations counts every iteration.
  bool iterate(std::vector<double>& psi, Stats& s, double targetL2, int budget,
               const std::function<void(int, double)>& progress, bool strict, double& firstStep) {
    constexpr double kCurveBelow = 0.9;  // curvedStep() for guarded steps shorter than this
    evaluateResidual(s);
    stageStartL2_ = s.l2;
    for (int k = 0;; ++k) {
      if (targetL2 < 0.0 ? s.maxLogError <= options_.stageLogError
                         : (s.l2 <= targetL2 && s.l1 <= options_.targetL1))
        return true;
      if (k >= budget) return false;
      // 1. Newton direction: J d = -r by GMRES, J the exact Jacobian of the areas at the current map.
      rhs_.resize(residual_.size());
      for (std::size_t c = 0; c < rhs_.size(); ++c) rhs_[c] = -residual_[c];
      newtonDirection(dirHat_);
      gradient(dirHat_, gradDir_);
      // 2. Its length (the exact line search); a step the fold guard cut short follows the curved path
      //    instead, once this level has needed to undo a continuation stage (curvedSteps_).
      double t = lineSearch();
      const double curved = curvedSteps_ && guardLimited_ && t > 0.0 && t < kCurveBelow ? curvedStep(t) : 0.0;
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
  // solve with the current LU factors (or the Laplacian's, before any): it need not be exact. Returns the
  // longest tau in {1, 0.8, 0.64, ...} above t at which every quad keeps an area above 1e-3 of its target
  // (those with a positive area now) and the merit is below the straight step's, or 0 when there is none.
  // Measured on sunrise (no suns split off): 66 Newton iterations became 24 at n = 512 (9.6 s against 15.5
  // s), 148 became 30 at n = 1024 (93 s against 164 s); interior at 512: 73 became 25 (12 s against 23 s).
  double curvedStep(double t) {
    const int n = n_;
    rhs_.resize(residual_.size());
    parallelChunks(threads_, n, 8, [&](int lo, int hi) {
      for (int j = lo; j < hi; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t p00 = vi(i, j), p10 = p00 + 1, p01 = p00 + v_, p11 = p01 + 1;
          rhs_[std::size_t(j) * n + i] =
              0.5 * cross2(gradDir_[p11] - gradDir_[p00], gradDir_[p01] - gradDir_[p10]);
        }
    });
    curveDir_.resize(residual_.size()), curveGrad_.resize(pos_.size());
    if (lu_)
      solveFrozenLu(rhs_, curveDir_, -1.0);
    else
      solveLaplacian(rhs_, curveDir_);  // -L^-1 a, L the Jacobian at the identity
    gradient(curveDir_, curveGrad_);
    const bool relative = options_.relativeResidual;
    // Merit (as lineSearch) and the number of quads that would come too close to degenerate, at psi + t1 d +
    // t2 d2.
    const auto evaluate = [&](double t1, double t2) {
      return reduceChunks<2>(threads_, n, 8, [&](int lo, int hi) {
        std::array<double, 2> acc{0.0, 0.0};
        for (int j = lo; j < hi; ++j)
          for (int i = 0; i < n; ++i) {
            const std::size_t p00 = vi(i, j), p10 = p00 + 1, p01 = p00 + v_, p11 = p01 + 1;
            const auto at = [&](std::size_t p) { return pos_[p] + t1 * gradDir_[p] + t2 * curveGrad_[p]; };
            const double area = 0.5 * cross2(at(p11) - at(p00), at(p01) - at(p10));
            const std::size_t c = std::size_t(j) * n + i;
            if (residual_[c] + mass_[c] > 0.0 && !(area > 1e-3 * mass_[c])) acc[1] += 1.0;
            const double r = (area - mass_[c]) / (relative ? mass_[c] : 1.0);
            acc[0] += r * r;
          }
        return acc;
      });
    };
    const double straight = evaluate(t, 0.0)[0];
    for (double tau = 1.0; tau > t; tau *= 0.8) {
      const auto [merit, degenerate] = evaluate(tau, tau * tau);
      if (degenerate == 0.0 && merit < straight) return tau;
    }
    return 0.0;
  }

  const std::vector<Vec2>& positions() const { return pos_; }

  // The quads that the map of psi folds, which a start must not have: those of area <= 0 (under the Convex
  // guard, those not strictly convex). Leaves that map in pos_.
  int foldedAt(std::span<const double> psi) {
    gradient(psi, pos_);
    for (int j = 0; j < v_; ++j)
      for (int i = 0; i < v_; ++i) pos_[vi(i, j)] += Vec2(double(i) / n_, double(j) / n_);
    if (options_.foldGuard == OtFoldGuard::Convex) return otFoldedQuads(pos_, n_);
    const std::vector<double> areas = otQuadAreas(pos_, n_);
    return int(std::count_if(areas.begin(), areas.end(), [](double a) { return !(a > 0.0); }));
  }

 private:
  std::size_t vi(int i, int j) const { return std::size_t(j) * v_ + i; }

  // Vertex gradients (the discretization of Nader & Guennebaud 2018): the 2x2 difference of the four cells around a vertex, with cell indices
  // clamped to the grid. Clamping gives exactly the boundary rule (normal component 0, tangential 1-D
  // difference, corners 0), so boundary vertices slide along the boundary.
  void gradient(std::span<const double> f, std::vector<Vec2>& g) {
    const int n = n_, w = n + 2;
    for (int j = 0; j < w; ++j) {
      const int sj = std::clamp(j - 1, 0, n - 1);
      for (int i = 0; i < w; ++i)
        pad_[std::size_t(j) * w + i] = f[std::size_t(sj) * n + std::clamp(i - 1, 0, n - 1)];
    }
    const double half = 0.5 * n;
    parallelChunks(threads_, v_, 16, [&](int lo, int hi) {
      for (int j = lo; j < hi; ++j) {
        const double* top = &pad_[std::size_t(j) * w];
        const double* bottom = top + w;
        for (int i = 0; i < v_; ++i) {
          const double a = top[i], b = top[i + 1], c = bottom[i], d = bottom[i + 1];
          // Differences first, so that equal clamped neighbours give an exact 0 on the boundary.
          g[vi(i, j)] = Vec2(half * ((b - a) + (d - c)), half * ((c - a) + (d - b)));
        }
      }
    });
  }

  // out = -L^-1 r in the DCT-II basis; the transposed layout in between is harmless because the spectrum
  // 1/lambda(k, l) is symmetric.
  void solveLaplacian(std::span<const double> r, std::vector<double>& out) {
    std::copy(r.begin(), r.end(), out.begin());
    dct_.forwardRows(out, threads_);
    transposeSquare(out, n_);
    dct_.forwardRows(out, threads_);
    for (std::size_t c = 0; c < out.size(); ++c) out[c] *= inverseEigen_[c];
    dct_.inverseRows(out, threads_);
    transposeSquare(out, n_);
    dct_.inverseRows(out, threads_);
  }

  // out = J x: the exact Jacobian of the areas at the current map applied to a potential x.
  void applyJacobian(std::span<const double> x, std::vector<double>& out) {
    gradient(x, gradDir_);
    parallelChunks(threads_, n_, 8, [&](int lo, int hi) {
      for (int j = lo; j < hi; ++j)
        for (int i = 0; i < n_; ++i) out[std::size_t(j) * n_ + i] = linearCoefficient(i, j, gradDir_);
    });
  }

  static double dot(std::span<const double> a, std::span<const double> b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
    return s;
  }

  // Inexact Newton: GMRES(m) on J d = -r, right-preconditioned by L^-1 (the DCT solve), d0 = 0 (Saad &
  // Schultz 1986). The first Krylov vector is the chord direction, so this is never worse than it in
  // ||r + J d||.
  enum class Preconditioner { Laplacian, FrozenLu };

  // z = M^-1 v: the fixed pseudo-Laplacian's inverse, or the LU factors of the Jacobian of an earlier map (a
  // lagged Jacobian: close to the current one within a continuation stage).
  void precondition(Preconditioner which, std::span<const double> v, std::vector<double>& z) {
    // GMRES works on the row-scaled system W J x = W b, so the preconditioner approximates
    // (W J)^-1 = J^-1 W^-1.
    unscaled_.resize(v.size());
    for (std::size_t c = 0; c < v.size(); ++c) unscaled_[c] = v[c] / rowScale_[c];
    if (which == Preconditioner::Laplacian) {
      solveLaplacian(unscaled_, z);
      for (double& x : z) x = -x;
      return;
    }
    solveFrozenLu(unscaled_, z, 1.0);
  }

  // out = sign * J^-1 rhs with the current LU factors (non-finite entries of the solution become 0), solved
  // in place in out (which must not alias rhs).
  void solveFrozenLu(std::span<const double> rhs, std::vector<double>& out, double sign) {
    const std::size_t size = std::size_t(n_) * n_;
    out.assign(rhs.begin(), rhs.begin() + std::ptrdiff_t(size));
    out[0] = 0.0;  // row 0 of the factored matrix is psi_0 = 0
    lu_->solve(out);
    for (double& x : out) x = std::isfinite(x) ? sign * x : 0.0;
  }

  // Newton direction: GMRES with the cheap Laplacian preconditioner while it reaches its tolerance; when it
  // does not (a strongly distorted map), GMRES preconditioned by the LU factors of the exact Jacobian,
  // refactored at the current map when the lagged factors no longer reach the tolerance either. A
  // factorisation costs about 11 solves at n = 512 and 14 at 1024 (0.07 s against 6.5 ms, 0.39 s against
  // 27 ms with grid_lu.h; it was 0.7 s against 0.047 s at 512 with UMFPACK), so lagged factors are kept as
  // long as GMRES fixes their mismatch in at most 4 steps (8 gave sunrise at n = 512 526 solves and 31 s,
  // against 314 and 21 s, with UMFPACK; with grid_lu.h's streamed solves, 6 or 8 steps made sunrise and city
  // at 512 20-50 % slower and interior and studio 10-30 % faster, measured). Renewing them whenever one
  // lagged step missed the tolerance (grid LU, n = 512) made city and sunrise 1.5-2x faster but studio,
  // sunset, forest and sun1e5 1.3-1.8x slower, and night and interior no faster. They are asked for a tighter
  // tolerance than fresh ones, which meet krylovTolerance in one or two steps and so give nearly exact
  // directions: lagged factors at krylovTolerance gave inexact directions that cost more Newton iterations
  // than the factorisations saved (measured). At 0.03 rather than 0.01 (alternating runs, smoothed starts):
  // night, interior and sunrise at n = 512 from 1.9-2.3 s to 1.7-2.0 s in the same iterations (+-1), night at
  // 1024 12.6 -> 10.9 s, the other maps within the noise or faster; 0.05 cost night and interior 4-6 more
  // iterations at 512. Of the lagged attempts that failed at 0.01, most ended at 0.01-0.03. A short step is
  // no sign of poor factors (the guard cuts the first step of most continuation stages): renewing them after
  // every short step made sunrise at n = 512 factorise 118 times without finishing in 240 s.
  void newtonDirection(std::vector<double>& d) {
    if (!laplacianFailed_) {
      if (gmres(d, Preconditioner::Laplacian) <= options_.krylovTolerance) return;
      laplacianFailed_ = true;
    }
    constexpr int kLaggedSteps = 4;
    constexpr double kLaggedTolerance = 0.03;
    if (lu_ && gmres(d, Preconditioner::FrozenLu, kLaggedSteps, kLaggedTolerance) <= kLaggedTolerance) return;
    factorJacobian();
    gmres(d, Preconditioner::FrozenLu);
  }

  // GMRES(m) on J d = rhs_ (= -r), right-preconditioned, d0 = 0 (Saad & Schultz 1986). Returns the reached
  // relative residual of the row-scaled system. The preconditioned basis vectors z_k = M^-1 v_k are kept, so
  // x = sum y_k z_k costs no further preconditioner solve (as flexible GMRES stores them, Saad 1993): at
  // n = 512 that spares one LU solve (18 ms) of the four or so behind each Newton direction.
  double gmres(std::vector<double>& d, Preconditioner which, int maxSteps = 0, double tolerance = 0.0) {
    const int m = maxSteps > 0 ? std::min(maxSteps, options_.krylovSteps) : options_.krylovSteps;
    if (tolerance <= 0.0) tolerance = options_.krylovTolerance;
    const std::size_t size = rhs_.size();
    // Krylov vectors are sized as the iteration reaches them: most directions take 1-4 steps, and sizing all
    // 2 m + 1 up front made the kernel zero 330 MB of fresh pages per level at n = 1024.
    basis_.resize(std::size_t(m + 1));
    preconditioned_.resize(std::size_t(m));
    basis_[0].resize(size);
    std::vector<double> h(std::size_t((m + 1) * m), 0.0), cs(static_cast<std::size_t>(m)),
        sn(static_cast<std::size_t>(m)), g(std::size_t(m + 1), 0.0);
    const auto H = [&](int row, int col) -> double& { return h[std::size_t(row * m + col)]; };
    // With relativeResidual the system is scaled row by row by 1/m, so that GMRES's 2-norm tolerance bounds
    // each quad's error relative to its own target, not to the largest quad's.
    rowScale_.assign(size, 1.0);
    if (options_.relativeResidual)
      for (std::size_t c = 0; c < size; ++c) rowScale_[c] = 1.0 / mass_[c];
    const double beta0 = std::sqrt(dotScaled(rhs_, rowScale_));
    if (!(beta0 > 0.0)) {
      std::fill(d.begin(), d.end(), 0.0);
      return 0.0;
    }
    for (std::size_t c = 0; c < size; ++c) basis_[0][c] = rhs_[c] * rowScale_[c] / beta0;
    g[0] = beta0;
    int k = 0;
    for (; k < m; ++k) {
      preconditioned_[std::size_t(k)].resize(size), basis_[std::size_t(k + 1)].resize(size);
      precondition(which, basis_[std::size_t(k)], preconditioned_[std::size_t(k)]);
      ++krylovSteps_;
      applyJacobian(preconditioned_[std::size_t(k)], basis_[std::size_t(k + 1)]);
      auto& w = basis_[std::size_t(k + 1)];
      for (std::size_t c = 0; c < size; ++c) w[c] *= rowScale_[c];
      for (int i = 0; i <= k; ++i) {  // modified Gram-Schmidt
        const double hik = dot(w, basis_[std::size_t(i)]);
        H(i, k) = hik;
        for (std::size_t c = 0; c < size; ++c) w[c] -= hik * basis_[std::size_t(i)][c];
      }
      const double norm = std::sqrt(dot(w, w));
      H(k + 1, k) = norm;
      for (int i = 0; i < k; ++i) {  // previous Givens rotations
        const double a = H(i, k), b = H(i + 1, k);
        H(i, k) = cs[std::size_t(i)] * a + sn[std::size_t(i)] * b;
        H(i + 1, k) = -sn[std::size_t(i)] * a + cs[std::size_t(i)] * b;
      }
      const double a = H(k, k), b = H(k + 1, k), rr = std::hypot(a, b);
      cs[std::size_t(k)] = rr > 0.0 ? a / rr : 1.0, sn[std::size_t(k)] = rr > 0.0 ? b / rr : 0.0;
      H(k, k) = rr, H(k + 1, k) = 0.0;
      g[std::size_t(k + 1)] = -sn[std::size_t(k)] * g[std::size_t(k)];
      g[std::size_t(k)] = cs[std::size_t(k)] * g[std::size_t(k)];
      if (!(norm > 1e-300)) {
        ++k;
        break;
      }
      for (double& v : w) v /= norm;
      if (std::abs(g[std::size_t(k + 1)]) <= tolerance * beta0) {
        ++k;
        break;
      }
    }
    std::vector<double> y(std::size_t(k), 0.0);
    for (int i = k - 1; i >= 0; --i) {
      double s = g[std::size_t(i)];
      for (int j = i + 1; j < k; ++j) s -= H(i, j) * y[std::size_t(j)];
      y[std::size_t(i)] = H(i, i) != 0.0 ? s / H(i, i) : 0.0;
    }
    std::fill(d.begin(), d.end(), 0.0);  // d = Z y
    for (int i = 0; i < k; ++i)
      for (std::size_t c = 0; c < size; ++c) d[c] += y[std::size_t(i)] * preconditioned_[std::size_t(i)][c];
    return std::abs(g[std::size_t(k)]) / beta0;
  }

  static double dotScaled(std::span<const double> a, std::span<const double> w) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * w[i] * a[i] * w[i];
    return s;
  }

  // LU factors of the exact Jacobian at the current map. J (n^2 x n^2, 3x3 cell stencil) is assembled from
  // the chain dA_c/dP_v (rotated diagonals) times dP_v/dpsi (the clamped 2x2 difference of gradient()). J's
  // rows sum to 0 (the total area is fixed) and constants are its null space, so row 0 is replaced by psi_0 =
  // 0 and the mean removed afterwards. The pattern never changes, so its ordering is computed once per level.
  void factorJacobian() {
    const int n = n_;
    if (!lu_) {
      // Nested dissection of the grid, computed once per level; from here on lu_ always holds factors.
      lu_.emplace(n, n, threads_);
      jacobian_ = StencilMatrix(n, n);
    }
    const double half = 0.5 * n;
    parallelChunks(threads_, n, 8, [&](int lo, int hi) {
      for (int j = lo; j < hi; ++j)
        for (int i = 0; i < n; ++i) {
          const int c = j * n + i;
          std::fill_n(jacobian_.values.begin() + std::ptrdiff_t(c) * 9, 9, 0.0);
          if (c == 0) {
            jacobian_.at(0, 0, 0) = 1.0;
            continue;
          }
          const std::size_t p00 = vi(i, j), p10 = p00 + 1, p01 = p00 + v_, p11 = p01 + 1;
          const Vec2 d1 = pos_[p11] - pos_[p00], d2 = pos_[p01] - pos_[p10];
          // b = ½ (d1 x e2 + e1 x d2), e1 = g11 - g00, e2 = g01 - g10.
          const Vec2 de1 = 0.5 * Vec2(d2.y, -d2.x), de2 = 0.5 * Vec2(-d1.y, d1.x);
          const std::array<std::pair<int, Vec2>, 4> corners{std::pair{0, -de1}, std::pair{1, -de2},
                                                            std::pair{2, de1},
                                                            std::pair{3, de2}};  // 00, 10, 11, 01
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

  // Linear coefficient of the area of cell (i, j) when the vertices move by t * g: with diagonals D1 = P11 -
  // P00, D2 = P01 - P10, A(t) = ½ (D1 + t E1) x (D2 + t E2) (Nader & Guennebaud 2018: the quad area and Algorithm 1's line search).
  double linearCoefficient(int i, int j, const std::vector<Vec2>& g) const {
    const std::size_t p00 = vi(i, j), p10 = p00 + 1, p01 = p00 + v_, p11 = p01 + 1;
    const Vec2 d1 = pos_[p11] - pos_[p00], d2 = pos_[p01] - pos_[p10];
    const Vec2 e1 = g[p11] - g[p00], e2 = g[p01] - g[p10];
    return 0.5 * (cross2(d1, e2) + cross2(e1, d2));
  }

  void evaluateResidual(Stats& s) {
    const int n = n_;
    const auto sums = reduceChunks<4>(
        threads_, n, 8,
        [&](int lo, int hi) {
          std::array<double, 4> acc{0.0, 0.0, 0.0, 0.0};
          for (int j = lo; j < hi; ++j)
            for (int i = 0; i < n; ++i) {
              const std::size_t p00 = vi(i, j), p10 = p00 + 1, p01 = p00 + v_, p11 = p01 + 1;
              const double area = 0.5 * cross2(pos_[p11] - pos_[p00], pos_[p01] - pos_[p10]);
              const std::size_t c = std::size_t(j) * n + i;
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

  // Exact line search along the vertex motion gradDir_: every area is r + b t + a t^2, so E(t) is a quartic
  // (the line search of Nader & Guennebaud 2018, Algorithm 1). The step is kept within boundaryFraction of the first t at which some quad
  // corner's cross product (P_next - P) x (P_prev - P), also quadratic in t, reaches 0: a convex quad stays
  // convex.
  double lineSearch() {
    const int n = n_;
    const OtFoldGuard guard = options_.foldGuard;
    const bool relative = options_.relativeResidual;
    // e0..e4, then the positive and negative step bounds (as minima of t and of -t).
    const auto sums = reduceChunks<7>(
        threads_, n, 8,
        [&](int lo, int hi) {
          std::array<double, 7> acc{0, 0, 0, 0, 0, -kInf, -kInf};
          double tPos = kInf, tNeg = kInf;
          for (int j = lo; j < hi; ++j)
            for (int i = 0; i < n; ++i) {
              const std::size_t p00 = vi(i, j), p10 = p00 + 1, p01 = p00 + v_, p11 = p01 + 1;
              const Vec2 d1 = pos_[p11] - pos_[p00], d2 = pos_[p01] - pos_[p10];
              const Vec2 e1 = gradDir_[p11] - gradDir_[p00], e2 = gradDir_[p01] - gradDir_[p10];
              double b = 0.5 * (cross2(d1, e2) + cross2(e1, d2)), a = 0.5 * cross2(e1, e2);
              double r = residual_[std::size_t(j) * n + i];
              if (relative) {
                const double w = 1.0 / mass_[std::size_t(j) * n + i];
                b *= w, a *= w, r *= w;
              }
              acc[0] += r * r, acc[1] += 2.0 * r * b, acc[2] += b * b + 2.0 * a * r, acc[3] += 2.0 * a * b;
              acc[4] += a * a;
              if (guard == OtFoldGuard::Area) {
                const double area = residual_[std::size_t(j) * n + i] + mass_[std::size_t(j) * n + i];
                if (relative) b *= mass_[std::size_t(j) * n + i], a *= mass_[std::size_t(j) * n + i];
                if (area > 0.0) {
                  tPos = std::min(tPos, firstPositiveRoot(area, b, a));
                  tNeg = std::min(tNeg, firstPositiveRoot(area, -b, a));
                }
                continue;
              }
              if (guard == OtFoldGuard::None) continue;
              // Corners counter-clockwise: 00, 10, 11, 01.
              const std::array<std::size_t, 4> ring{p00, p10, p11, p01};
              for (int k = 0; k < 4; ++k) {
                const std::size_t pc = ring[std::size_t(k)], pn = ring[std::size_t((k + 1) & 3)],
                                  pp = ring[std::size_t((k + 3) & 3)];
                const Vec2 u = pos_[pn] - pos_[pc], du = gradDir_[pn] - gradDir_[pc];
                const Vec2 w = pos_[pp] - pos_[pc], dw = gradDir_[pp] - gradDir_[pc];
                const double c0 = cross2(u, w);
                if (!(c0 > 0.0)) continue;  // already degenerate: not a constraint
                const double c1 = cross2(u, dw) + cross2(du, w), c2 = cross2(du, dw);
                tPos = std::min(tPos, firstPositiveRoot(c0, c1, c2));
                tNeg = std::min(tNeg, firstPositiveRoot(c0, -c1, c2));
              }
            }
          acc[5] = -tPos, acc[6] = -tNeg;
          return acc;
        },
        {false, false, false, false, false, true, true});
    Quartic q;
    for (int k = 0; k < 5; ++k) q.e[std::size_t(k)] = sums[std::size_t(k)];
    constexpr double kMaxStep = 10.0;  // as Nader & Guennebaud 2018's released solver (github.com/ggael/otmap)
    const double hi = std::min(kMaxStep, options_.boundaryFraction * -sums[5]);
    const double lo = -std::min(kMaxStep, options_.boundaryFraction * -sums[6]);
    const double t = minimiseQuartic(q, lo, hi);
    guardLimited_ = hi < kMaxStep && t >= hi * (1.0 - 1e-12);
    // Require a real decrease, not one lost in rounding.
    if (!(q.value(t) < q.e[0] * (1.0 - 1e-12))) return 0.0;
    return t;
  }

  int n_, v_, threads_;
  const OtSolverOptions& options_;
  std::vector<double> rhs_, rowScale_, unscaled_;
  DctPlan dct_;
  std::vector<double> mass_, inverseEigen_, residual_, dirHat_, pad_;
  std::vector<Vec2> pos_, gradDir_, curveGrad_;
  std::vector<double> curveDir_;
  bool guardLimited_ = false;  // the last lineSearch() stopped at the fold guard's bound
  bool curvedSteps_ = false;   // curvedStep() is in use on this level
  double stageStartL2_ = 0.0;  // E when the last iterate() started, against that stage's target
  int curvedStepsTaken_ = 0;
  std::vector<std::vector<double>> basis_, preconditioned_;
  StencilMatrix jacobian_;
  std::optional<GridLu> lu_;
  bool laplacianFailed_ = false;
  int factorisations_ = 0, krylovSteps_ = 0;
};

// 2x2 box restriction: keeps the mean (and so the total mass) exactly.
std::vector<double> restrictDensity(std::span<const double> rho, int n) {
  const int m = n / 2;
  std::vector<double> out(std::size_t(m) * m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const std::size_t a = std::size_t(2 * j) * n + 2 * i, b = a + n;
      out[std::size_t(j) * m + i] = 0.25 * (rho[a] + rho[a + 1] + rho[b] + rho[b + 1]);
    }
  return out;
}

// Coarse psi (m x m) to the fine grid (2m x 2m): psi averaged over the four cells around each coarse vertex,
// then interpolated bilinearly between the coarse vertices at the fine cell centres. The average removes the
// checkerboard (-1)^(i+j), which the 2x2 gradient stencil does not see at interior vertices (Nader & Guennebaud 2018),
// so a converged coarse psi can carry any amount of it; interpolated directly from the cell centres it became
// steep fine gradients (measured: 30-45 % of the fine quads folded on every real map and sun, so every level
// had restarted from the identity). Averaging psi keeps x^2/2 + psi convex where it was (a mean of convex
// functions), so the prolonged map stays monotone away from the coarse map's twisted quads. psi is a
// function on the unit square, so no rescaling.
std::vector<double> prolongPotential(std::span<const double> psi, int m) {
  const int n = 2 * m, v = m + 1;
  std::vector<double> corner(std::size_t(v) * v);
  for (int y = 0; y < v; ++y)
    for (int x = 0; x < v; ++x) {
      const int x0 = std::clamp(x - 1, 0, m - 1), x1 = std::clamp(x, 0, m - 1);
      const int y0 = std::clamp(y - 1, 0, m - 1), y1 = std::clamp(y, 0, m - 1);
      corner[std::size_t(y) * v + x] = 0.25 * (psi[std::size_t(y0) * m + x0] + psi[std::size_t(y0) * m + x1] +
                                               psi[std::size_t(y1) * m + x0] + psi[std::size_t(y1) * m + x1]);
    }
  std::vector<double> out(std::size_t(n) * n);
  for (int j = 0; j < n; ++j) {
    const double y = 0.5 * (j + 0.5);  // fine cell centre in coarse cell units, the coarse vertices at 0..m
    const int y0 = std::min(int(y), m - 1);
    const double wy = y - y0;
    for (int i = 0; i < n; ++i) {
      const double x = 0.5 * (i + 0.5);
      const int x0 = std::min(int(x), m - 1);
      const double wx = x - x0;
      const auto at = [&](int a, int b) { return corner[std::size_t(b) * v + a]; };
      out[std::size_t(j) * n + i] = (1 - wy) * ((1 - wx) * at(x0, y0) + wx * at(x0 + 1, y0)) +
                                    wy * ((1 - wx) * at(x0, y0 + 1) + wx * at(x0 + 1, y0 + 1));
    }
  }
  double mean = 0.0;
  for (double value : out) mean += value;
  mean /= double(out.size());
  for (double& value : out) value -= mean;
  return out;
}

// psi (n x n) smoothed by `passes` binomial passes [1 2 1] / 4 along rows and then columns, with the
// reflecting boundary of the gradient stencil. Each pass's matrix is doubly stochastic, so the mean of psi
// (0) is kept.
void smoothPotential(std::vector<double>& psi, int n, int passes) {
  std::vector<double> rows(psi.size());
  const auto at = [n](int i, int j) { return std::size_t(j) * n + i; };
  for (int pass = 0; pass < passes; ++pass) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        rows[at(i, j)] = 0.25 * (psi[at(std::max(i - 1, 0), j)] + 2.0 * psi[at(i, j)] +
                                 psi[at(std::min(i + 1, n - 1), j)]);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        psi[at(i, j)] = 0.25 * (rows[at(i, std::max(j - 1, 0))] + 2.0 * rows[at(i, j)] +
                                rows[at(i, std::min(j + 1, n - 1))]);
  }
}

// Smooths a folded psi by 1, 1, 2, 4, ... more passes (1, 2, 4, 8, ... in all) until the solver accepts it as
// a start or the next batch would pass maxPasses. Sets `passes` to the passes made; returns the quads still
// folded (0 once accepted; at least one when no pass was allowed).
int smoothUntilUnfolded(LevelSolver& solver, std::vector<double>& psi, int n, int maxPasses, int& passes) {
  passes = 0;
  int folded = 1;  // psi comes in folded
  for (int batch = 1; folded > 0 && passes + batch <= maxPasses; batch = passes) {
    smoothPotential(psi, n, batch);
    passes += batch;
    folded = solver.foldedAt(psi);
  }
  return folded;
}

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
    const std::vector<double> coarse = restrictDensity(rho, n);
    LevelResult c = solveLevels(coarse, n / 2, options, false);
    result.coarseIterations = c.coarseIterations + c.stats.iterations;
    result.psi = prolongPotential(c.psi, n / 2);
    result.laplacianFailed = c.laplacianFailed;
    result.levels = std::move(c.levels);
  } else {
    result.psi.assign(std::size_t(n) * n, 0.0);
  }
  const auto start = std::chrono::steady_clock::now();
  OtLevelStats level;
  level.n = n;
  LevelSolver solver(n, rho, options);
  if (result.laplacianFailed) solver.setLuFirst();
  const double target = finest ? options.targetL2 : std::max(options.targetL2, options.coarseTargetL2);
  const std::function<void(int, double)> progress = finest ? options.progress : nullptr;
  // The converged coarse map has non-convex quads wherever it compresses strongly (next to suns and lamps:
  // 30 % of the quads of night at n = 512), and the prolonged potential folds fine quads there. A binomial
  // pass damps a wavelength of k cells by cos^2(pi / k) per axis: the two-cell twist goes, the transport at
  // the scale of the coarse grid stays. Measured (iblx_ot_bench): 1-8 passes unfolded every folded start of
  // the 13 benchmark densities at n = 16-1024. The start this replaced (continue from the folded map, and
  // after three stages restart 14-50 % of the way from the identity) was, alternating in one
  // run, 1.5-1.7x slower on night and interior at n = 512 (3.8-3.9 s against 2.2-2.5 s) and 1.3-1.8x at
  // 1024 (17-19 s against 11-13 s), 2x on sun1e5 at 1024; studio at 512 lost 15 % (8 passes on its 4 639
  // folded quads). Smoothing only near the folded quads folded new ones at the edge of the smoothed region.
  level.startFoldedQuads = solver.foldedAt(result.psi);
  if (level.foldedStart()) {
    if (smoothUntilUnfolded(solver, result.psi, n, options.maxSmoothingPasses, level.smoothingPasses) > 0) {
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
  // 1) and retried with half the nominal step could land on s = 1 again and repeat the failed stage exactly
  // (seen on interior at n = 1024).
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

std::vector<double> otDensityFromEnv(const EnvImage& env, int n) {
  // Texel masses w = L * Omega(y) (solid angle included); texelSamplingWeights validates the image and maps
  // an all-black image to the uniform sphere.
  return otDensityFromWeights(texelSamplingWeights(env, "OT density"), env.width, env.height, n);
}

std::vector<double> otDensityFromWeights(std::span<const double> weights, int width, int height, int n) {
  if (n < 1) throw Error("OT density: the grid size must be at least 1, got " + std::to_string(n));
  if (width < 1 || height < 1 || weights.size() != std::size_t(width) * height)
    throw Error("OT density: expected " + std::to_string(width) + " x " + std::to_string(height) +
                " weights");
  const auto index = [width](int x, int y) { return std::size_t(y) * width + x; };
  // Pass 1, along u: per texel row y, the texel mass falling in each grid column (exact length overlap).
  std::vector<double> rows(std::size_t(height) * n, 0.0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double w = weights[index(x, y)];
      if (w == 0.0) continue;
      const double u0 = double(x) / width, u1 = double(x + 1) / width;
      for (int c = std::max(0, int(std::floor(u0 * n))); c < std::min(n, int(std::ceil(u1 * n))); ++c) {
        const double overlap = std::min(u1, double(c + 1) / n) - std::max(u0, double(c) / n);
        if (overlap > 0.0) rows[std::size_t(y) * n + c] += w * overlap * width;
      }
    }
  // Pass 2, along v: the share of texel row y's solid angle inside grid row r is (cos ta - cos tb) / (cos t0
  // - cos t1) over the overlap [ta, tb], exact for the nearest-texel radiance (dOmega = dphi dcos(theta)).
  const auto cosDiff = [](double a, double b) {  // cos(pi a) - cos(pi b) without cancellation
    return 2.0 * std::sin(0.5 * kPi * (a + b)) * std::sin(0.5 * kPi * (b - a));
  };
  std::vector<double> density(std::size_t(n) * n, 0.0);
  for (int y = 0; y < height; ++y) {
    const double v0 = double(y) / height, v1 = double(y + 1) / height, full = cosDiff(v0, v1);
    for (int r = std::max(0, int(std::floor(v0 * n))); r < std::min(n, int(std::ceil(v1 * n))); ++r) {
      const double a = std::max(v0, double(r) / n), b = std::min(v1, double(r + 1) / n);
      if (b <= a) continue;
      const double share = cosDiff(a, b) / full;
      for (int c = 0; c < n; ++c) density[std::size_t(r) * n + c] += share * rows[std::size_t(y) * n + c];
    }
  }
  double total = 0.0;
  for (double v : density) total += v;
  if (!(total > 0.0)) throw Error("OT density: the weights are zero everywhere");
  const double scale = double(n) * n / total;  // cells have equal parameter area: mass -> mean-1 density
  for (double& v : density) v *= scale;
  return density;
}

}  // namespace iblx
