// Error metrics over object pixels.
#include "engine/render/metrics.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace iblx {

double relativeErrorWeight(double r) {
  return 1.0 / (r * r + 0.01);
}

namespace {
double relativeSquaredError(double x, double r) {
  return (x - r) * (x - r) * relativeErrorWeight(r);
}
}  // namespace

ErrorMetrics compareToReference(const GBuffer& gbuffer, std::span<const float> estimate,
                                std::span<const float> reference) {
  if (estimate.size() != reference.size() || estimate.size() != gbuffer.pixels.size() * 3)
    throw Error("image and reference sizes differ");
  ErrorMetrics m;
  for (size_t i = 0; i < gbuffer.pixels.size(); ++i) {
    if (gbuffer.pixels[i].normal.w == 0.0f) continue;
    ++m.pixels;
    for (int c = 0; c < 3; ++c) {
      const double x = estimate[3 * i + c], r = reference[3 * i + c], d = x - r;
      m.mse += d * d;
      m.relMse += relativeSquaredError(x, r);
      m.meanSignedError += d;
    }
  }
  if (m.pixels) {
    const double n = 3.0 * double(m.pixels);
    m.mse /= n;
    m.relMse /= n;
    m.meanSignedError /= n;
  }
  return m;
}

std::vector<double> relativeSquaredErrorPerPixel(const GBuffer& gbuffer, std::span<const float> estimate,
                                                 std::span<const float> reference) {
  if (estimate.size() != reference.size() || estimate.size() != gbuffer.pixels.size() * 3)
    throw Error("image and reference sizes differ");
  std::vector<double> error(gbuffer.pixels.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < gbuffer.pixels.size(); ++i) {
    if (gbuffer.pixels[i].normal.w == 0.0f) continue;
    double sum = 0;
    for (int c = 0; c < 3; ++c) sum += relativeSquaredError(estimate[3 * i + c], reference[3 * i + c]);
    error[i] = sum / 3.0;
  }
  return error;
}

double MeanErrorZTest::maxAbsZ() const {
  return std::max({std::abs(z[0]), std::abs(z[1]), std::abs(z[2])});
}

MeanErrorZTest zTestMeanError(const GBuffer& gbuffer, std::span<const float> mean,
                              std::span<const float> variance, double samplesPerPixel,
                              std::span<const float> reference) {
  if (mean.size() != reference.size() || variance.size() != mean.size() ||
      mean.size() != gbuffer.pixels.size() * 3)
    throw Error("image, variance and reference sizes differ");
  MeanErrorZTest t;
  double count = 0;
  double sum[3] = {0, 0, 0}, varianceSum[3] = {0, 0, 0};
  for (size_t i = 0; i < gbuffer.pixels.size(); ++i) {
    if (gbuffer.pixels[i].normal.w == 0.0f) continue;
    ++count;
    for (int c = 0; c < 3; ++c) {
      sum[c] += double(mean[3 * i + c]) - reference[3 * i + c];
      varianceSum[c] += variance[3 * i + c] / samplesPerPixel;
    }
  }
  if (count == 0) return t;
  for (int c = 0; c < 3; ++c) {
    t.meanError[c] = sum[c] / count;
    t.standardError[c] = std::sqrt(varianceSum[c]) / count;
    t.z[c] = t.standardError[c] > 0 ? t.meanError[c] / t.standardError[c]
                                    : (std::abs(t.meanError[c]) < 1e-5 ? 0.0 : 1e9);
  }
  return t;
}

}  // namespace iblx
