// Error of an image against its reference over object pixels (docs/DESIGN.md §7): MSE, relMSE with eps =
// 0.01, and the mean signed error with its standard error (for unbiasedness z-tests).
#pragma once

#include "engine/geometry/gbuffer.h"

#include <span>
#include <vector>

namespace iblx {

struct ErrorMetrics {
  double mse = 0.0;              // mean over object pixels and channels of (x - r)^2
  double relMse = 0.0;           // mean of (x - r)^2 / (r^2 + 0.01)
  double meanSignedError = 0.0;  // mean of (x - r)
  std::size_t pixels = 0;
};

ErrorMetrics compareToReference(const GBuffer& gbuffer, std::span<const float> estimate,
                                std::span<const float> reference);

// docs/DESIGN.md §7: relMSE weighs a squared error at reference value r by 1 / (r^2 + 0.01) (eps = 0.01 for
// dark pixels).
double relativeErrorWeight(double r);

// Per-pixel squared error relative to the reference, (x - r)^2 / (r^2 + 0.01) averaged over the channels, for
// heat maps; NaN for background pixels.
std::vector<double> relativeSquaredErrorPerPixel(const GBuffer& gbuffer, std::span<const float> estimate,
                                                 std::span<const float> reference);

// Unbiasedness z-test (docs/DESIGN.md §5) of the image-mean signed error per channel: the sum over object
// pixels of (x_p - r_p) divided by its standard deviation sqrt(sum var_p / N), pixels being independent and
// var_p the measured per-pixel variance of one sample's estimate. A zero-variance image must match to float
// rounding.
struct MeanErrorZTest {
  double z[3] = {0, 0, 0};
  double meanError[3] = {0, 0, 0};
  double standardError[3] = {0, 0, 0};
  double maxAbsZ() const;
};
MeanErrorZTest zTestMeanError(const GBuffer& gbuffer, std::span<const float> mean,
                              std::span<const float> variance, double samplesPerPixel,
                              std::span<const float> reference);

}  // namespace iblx
