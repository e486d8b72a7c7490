// Error metrics over object pixels.
#include "engine/render/metrics.h"

#include "engine/core/error.h"

namespace iblx {

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
      m.relMse += d * d / (r * r + 0.01);
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

}  // namespace iblx
