// Error of an image against its reference over object pixels (DESIGN §7): MSE, relMSE with eps = 0.01, and
// the mean signed error with its standard error (for unbiasedness z-tests).
#pragma once

#include "engine/geometry/gbuffer.h"

#include <span>

namespace iblx {

struct ErrorMetrics {
  double mse = 0.0;              // mean over object pixels and channels of (x - r)^2
  double relMse = 0.0;           // mean of (x - r)^2 / (r^2 + 0.01)
  double meanSignedError = 0.0;  // mean of (x - r)
  std::size_t pixels = 0;
};

ErrorMetrics compareToReference(const GBuffer& gbuffer, std::span<const float> estimate,
                                std::span<const float> reference);

}  // namespace iblx
