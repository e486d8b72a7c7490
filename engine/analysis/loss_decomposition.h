// Where a sampler loses at equal time against a baseline, in factors (docs/STUDIES.md, "Decomposition"):
// the ratio R of equal-time MSE with `sobol` splits exactly into the pdf's variance per sample (from the
// `random` runs), the interaction with QMC at equal spp, the cost per sample, and a residual that measures
// how far the baseline's `sobol` curve is from its fitted power law. Plain CPU code on recorded curves
// (engine/analysis/convergence.h), so each factor can be unit-tested on synthetic curves.
#pragma once

#include "engine/analysis/convergence.h"

#include <span>
#include <string>
#include <vector>

namespace iblx {

// One sampler's runs: every seed with `random` and every seed with `sobol`.
struct SamplerRuns {
  std::string name;
  std::vector<ConvergenceRun> random, sobol;
};

// A curve over seeds: the median MSE and GPU time point by point, over the points every seed reached.
struct MedianCurve {
  std::vector<double> spp, mse, gpuSeconds;
  double slope = 0.0;  // log-log slope of MSE against spp over the tail (fitLogLogSlope)
};
// Points whose MSE is not a positive number (below a Monte Carlo reference's noise) are left out. Throws
// iblx::Error when fewer than 3 points remain.
MedianCurve medianCurve(std::span<const ConvergenceRun> seeds, const std::string& what);

// The tail of a curve that fits use: the first two points of six or more are skipped (as `converge` does).
std::size_t fitStart(const MedianCurve& curve);
// C of MSE = C / spp with the slope fixed at -1: the geometric mean of MSE x spp over the tail.
double varianceConstant(const MedianCurve& curve);
// MSE at spp n: log-log interpolation, extrapolated with the fitted slope beyond either end.
double mseAtSpp(const MedianCurve& curve, double n);
// spp at GPU time t: linear in time between points, proportional before the first and after the last.
double sppAtTime(const MedianCurve& curve, double t);

struct LossFactors {
  std::string name;
  double c = 0.0, cRatio = 0.0;  // (i) variance per sample with random numbers, and over the baseline's
  double q = 0.0;                // (ii) sobol MSE over C / N at the spp N reached at equal time
  double slopeRandom = 0.0, slopeSobol = 0.0;
  double nsPerSample = 0.0;  // (iii) GPU time over spp x object pixels of the sobol runs
  double spp = 0.0;          // N, the spp reached at equal time with sobol
  double ratio = 0.0;        // R: equal-time sobol MSE over the baseline's
  double pdf = 0.0, qmc = 0.0, cost = 0.0, residual = 0.0;  // R = pdf x qmc x cost x residual
};

struct LossDecomposition {
  double equalTimeSeconds = 0.0;  // T: the end of the shortest sobol curve (GPU time)
  double baselineSpp = 0.0;       // N_h
  double baselineSlope = 0.0;     // b_h
  std::vector<LossFactors> rows;  // in the order of `samplers`
};

// Decomposes every sampler's loss against samplers[baseline]; `objectPixels` converts GPU time per spp into
// time per sample. Throws iblx::Error naming a sampler without enough points.
LossDecomposition decomposeLoss(std::span<const SamplerRuns> samplers, std::size_t baseline,
                                std::size_t objectPixels);

}  // namespace iblx
