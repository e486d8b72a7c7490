// Rational functions fitted to samples, as ALTA's rational fitters write them to function files: linear
// least squares as in Pacanowski et al. 2012, "Rational BRDF", IEEE TVCG 18(11).
#pragma once

#include "engine/io/alta_func.h"

#include <span>
#include <vector>

namespace iblx {

// A rational function of total degree `degreeP` over `degreeQ` in the Chebyshev basis, per channel, over
// samples x (dimX each) with values y (per channel): linear least squares on P(x) - y Q(x) = 0 with Q's
// constant coefficient fixed to 1 (the normalisation), rows weighted by 1 / (y + 0.01 mean y) so the fit
// minimises relative error. A channel whose Q is not positive at every sample is refitted as a polynomial
// (Q = 1). Returns the lobe and sets rmsRelative = sqrt(mean((fit - y)^2 / (y^2 + 0.01))) over all channels.
struct AltaFitResult {
  AltaRational rational;
  double rmsRelative = 0.0;
};
AltaFitResult fitAltaRational(int dimX, std::span<const double> x, std::span<const std::vector<double>> y,
                              std::span<const double> min, std::span<const double> max, int degreeP,
                              int degreeQ);

}  // namespace iblx
