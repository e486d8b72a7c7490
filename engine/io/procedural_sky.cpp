// Analytic sky model for the default environment map. It is not a physical atmosphere (no Preetham/Hosek):
// only smooth, plausible gradients plus a sun disc, chosen so that the sampling hard cases are present.
#include "engine/io/procedural_sky.h"

#include "engine/core/error.h"
#include "engine/core/sphere_mapping.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace iblx {
namespace {

// Linear RGB radiances. The sky is blue at the zenith and whiter, brighter at the horizon; the ground is a
// dim brownish green (albedo ~0.15 under this sky), darkest straight down.
const glm::dvec3 kZenith{0.30, 0.45, 0.90};
const glm::dvec3 kSkyHorizon{1.15, 1.30, 1.50};
const glm::dvec3 kGroundHorizon{0.19, 0.18, 0.11};
const glm::dvec3 kGroundNadir{0.07, 0.07, 0.045};
// Slightly warm sun; the mean of R, G, B is exactly 1 so sunRadiance is the texel sampling weight (DESIGN
// §3).
const glm::dvec3 kSunTint{1.05, 1.00, 0.95};
// Half-width (in sin(elevation)) of the band where ground blends into sky: about 1 degree, so the horizon is
// sharp at the default resolution yet the function stays continuous.
constexpr double kHorizonBand = 0.0175;

double smoothStep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Angle between unit vectors, via atan2 so it stays accurate for the small angles of the sun disc.
double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

struct SkyModel {
  glm::dvec3 sunDirection;
  double sunRadius, sunRadiance, glowRadiance, glowWidth;

  // Radiance arriving from direction w (world, +Y up).
  glm::dvec3 radiance(const glm::dvec3& w) const {
    const double y = w.y;  // sin(elevation)
    // Sky: brightening towards the horizon as (1 - y)^3, a cheap stand-in for the longer path through the air
    // (more in-scattered light) at low elevations.
    const glm::dvec3 sky = glm::mix(kZenith, kSkyHorizon, std::pow(1.0 - std::max(y, 0.0), 3.0));
    // Ground: linear in depth below the horizon.
    const glm::dvec3 ground = glm::mix(kGroundHorizon, kGroundNadir, std::max(-y, 0.0));
    const double skyness = smoothStep(-kHorizonBand, kHorizonBand, y);
    glm::dvec3 result = glm::mix(ground, sky, skyness);

    // Sun and glow are scaled by `skyness` too, so a sun set below the horizon is hidden by the ground.
    const double gamma = angleBetween(w, sunDirection);
    double sun = glowRadiance * std::exp(-gamma / glowWidth);
    if (gamma < sunRadius) sun += sunRadiance;  // a uniform disc: its edge is anti-aliased by supersampling
    return result + skyness * sun * kSunTint;
  }
};

}  // namespace

EnvImage makeProceduralSky(const ProceduralSkyOptions& options) {
  const auto invalid = [](const std::string& what) { return Error("procedural sky: " + what); };
  if (options.width < 2 || options.height < 1) throw invalid("size must be at least 2x1");
  if (options.supersampling < 1) throw invalid("supersampling must be >= 1");
  if (!(options.sunAngularRadiusDegrees > 0.0 && options.sunAngularRadiusDegrees < 90.0))
    throw invalid("sun angular radius must be in (0, 90) degrees");
  if (!(options.sunRadiance >= 0.0 && options.glowRadiance >= 0.0) || !std::isfinite(options.sunRadiance) ||
      !std::isfinite(options.glowRadiance))
    throw invalid("sun and glow radiance must be finite and >= 0");
  if (!(options.glowAngularWidthDegrees > 0.0)) throw invalid("glow angular width must be > 0");
  if (!std::isfinite(options.sunElevationDegrees) || !std::isfinite(options.sunAzimuthDegrees))
    throw invalid("sun direction must be finite");

  // The sun direction in the lat-long convention of docs/DESIGN.md §3: theta = 90 deg - elevation, phi = azimuth.
  constexpr double kDegree = kPi / 180.0;
  const double sunU = options.sunAzimuthDegrees / 360.0 - std::floor(options.sunAzimuthDegrees / 360.0);
  const double sunV = (90.0 - options.sunElevationDegrees) / 180.0;
  const SkyModel model{latLongToDirection({sunU, sunV}), options.sunAngularRadiusDegrees * kDegree,
                       options.sunRadiance, options.glowRadiance, options.glowAngularWidthDegrees * kDegree};

  EnvImage image;
  image.width = options.width;
  image.height = options.height;
  image.rgb.resize(3 * image.texelCount());
  const int n = options.supersampling;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      // Texel value = mean radiance over the texel's solid angle: an n x n grid of sub-texel centres, each
      // weighted by sin(theta) (the lat-long area element), so that value x exact texel solid angle is the
      // energy the texel receives, which is what the samplers and the reference integrate.
      glm::dvec3 sum(0.0);
      double weightSum = 0.0;
      for (int j = 0; j < n; ++j) {
        const double v = (y + (j + 0.5) / n) / image.height;
        const double sinTheta = std::sin(kPi * v);  // > 0: sub-texel centres never sit on a pole
        for (int i = 0; i < n; ++i) {
          const double u = (x + (i + 0.5) / n) / image.width;
          sum += sinTheta * model.radiance(latLongToDirection({u, v}));
          weightSum += sinTheta;
        }
      }
      const glm::dvec3 mean = sum / weightSum;
      float* out = &image.rgb[3 * image.index(x, y)];
      for (int c = 0; c < 3; ++c) out[c] = float(mean[c]);
    }
  }
  return image;
}

}  // namespace iblx
