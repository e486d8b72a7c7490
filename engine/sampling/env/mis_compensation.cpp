// MIS compensation of an environment map's sampling density (mis_compensation.h).
#include "engine/sampling/env/mis_compensation.h"

#include "engine/io/latlong_texel.h"

#include <algorithm>

namespace iblx {

EnvImage misCompensated(const EnvImage& image) {
  const std::vector<double> weights = texelSamplingWeights(image, "mis compensation");  // m * solid angle
  double total = 0.0;
  for (double w : weights) total += w;
  const double mean = total / (4.0 * kPi);  // mu: the mean of m over the sphere
  EnvImage out = image;
  bool anyLeft = false;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      // Within 1e-6 of the mean counts as at the mean: the sum of the texels' solid angles is 4 pi only up to
      // rounding, and a constant map must not keep a residue of it.
      const double excess = image.weight(x, y) - mean;
      const double m = excess > 1e-6 * mean ? excess : 0.0;
      const std::size_t i = 3 * image.index(x, y);
      out.rgb[i] = out.rgb[i + 1] = out.rgb[i + 2] = float(m);
      anyLeft = anyLeft || float(m) > 0.0f;
    }
  return anyLeft ? out : image;
}

}  // namespace iblx
