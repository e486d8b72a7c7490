// The within-texel warp shared by the texel-based env samplers (env-cdf, env-hier) and their GLSL twins:
// texel (x, y) + t in [0,1)^2 -> direction, uniform in phi and in cos(theta) so the density is constant per
// texel.
#pragma once

#include "engine/core/error.h"
#include "engine/core/log.h"
#include "engine/io/env_image.h"
#include "engine/core/sphere_mapping.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace iblx {

// Largest float below 1: every remapped uniform sample is clamped to [0, kOneMinusEpsilonF] as on the GPU.
inline constexpr float kOneMinusEpsilonF = 0x1.fffffep-1f;

// A uniform sample in [0,1) as the GPU receives it: rounded to float and kept below 1.
inline float toGpuU(double u) {
  return std::clamp(float(u), 0.0f, kOneMinusEpsilonF);
}

// Result of a texel-based environment sampler (CPU twin).
struct EnvSample {
  glm::dvec3 direction{0.0, 1.0, 0.0};
  double pdfSolidAngle =
      0.0;  // density w.r.t. solid angle of `direction`; 0 = the sample contributes nothing
  glm::ivec2 texel{0};
};

// A direction that pdf() and invert() can locate: finite and not the zero vector.
inline bool isUsableDirection(glm::dvec3 w) {
  return std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z) && glm::dot(w, w) > 0.0;
}

// Texel (x, y) of a W x H lat-long map and t in [0,1)^2 -> direction with phi = 2*pi*(x + t.x)/W and
// cos(theta) = cos(theta0) + t.y * (cos(theta1) - cos(theta0)), theta0 = pi*y/H, theta1 = pi*(y+1)/H.
// Uniform t gives the constant density 1/Omega(y) w.r.t. solid angle (Archimedes: dOmega = dphi dcos(theta)).
inline glm::dvec3 texelToDirection(int x, int y, glm::dvec2 t, int width, int height) {
  const double phi = 2.0 * kPi * (x + t.x) / width;
  const double cos0 = std::cos(kPi * y / height), cos1 = std::cos(kPi * (y + 1) / height);
  const double cosTheta = std::clamp(cos0 + t.y * (cos1 - cos0), -1.0, 1.0);
  const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
  return {sinTheta * std::cos(phi), cosTheta, sinTheta * std::sin(phi)};
}

// The texel that contains direction w (need not be normalised), via directionToLatLong, clamped to the map.
inline glm::ivec2 directionToTexel(glm::dvec3 w, int width, int height) {
  const glm::dvec2 uv = directionToLatLong(w);
  const int x = std::clamp(int(std::floor(uv.x * width)), 0, width - 1);
  const int y = std::clamp(int(std::floor(uv.y * height)), 0, height - 1);
  return {x, y};
}

// Inverse of the t mapping of texelToDirection for a direction inside (or on the border of) `texel`.
inline glm::dvec2 directionToTexelOffset(glm::dvec3 w, glm::ivec2 texel, int width, int height) {
  const glm::dvec2 uv = directionToLatLong(w);
  double tx = uv.x * width - texel.x;
  if (tx < -0.5 * width) tx += width;  // phi wrapped to 0 on the last column
  const double cos0 = std::cos(kPi * texel.y / height), cos1 = std::cos(kPi * (texel.y + 1) / height);
  const double ty = (w.y / glm::length(w) - cos0) / (cos1 - cos0);
  return {std::clamp(tx, 0.0, 1.0), std::clamp(ty, 0.0, 1.0)};
}

// Omega(y) = latLongTexelSolidAngle(y, W, H) for every row, computed in double, stored as float (GPU array).
inline std::vector<float> rowSolidAngles(int width, int height) {
  std::vector<float> omega(std::size_t(std::max(height, 0)));
  for (int y = 0; y < height; ++y) omega[std::size_t(y)] = float(latLongTexelSolidAngle(y, width, height));
  return omega;
}

// Per-row table of the GPU (set 0, binding 3), one vec4 per row: the texel solid angle Omega(y), and the
// squared half-angle terms a0, a1 at the row's top and bottom edges, a = sin^2(theta/2) for rows in the upper
// half and cos^2(theta/2) in the lower half (w = 1 there), so that shaders/lib/latlong.glsl maps t.y to
// cos(theta) without trigonometry and without cancellation next to either pole.
inline std::vector<float> envRowTable(int width, int height) {
  std::vector<float> rows(4 * std::size_t(std::max(height, 0)));
  for (int y = 0; y < height; ++y) {
    const bool lower = 2 * y >= height;
    const double h0 = 0.5 * kPi * y / height, h1 = 0.5 * kPi * (y + 1) / height;
    const double a0 = lower ? std::cos(h0) : std::sin(h0), a1 = lower ? std::cos(h1) : std::sin(h1);
    float* r = &rows[4 * std::size_t(y)];
    r[0] = float(latLongTexelSolidAngle(y, width, height));
    r[1] = float(a0 * a0);
    r[2] = float(a1 * a1);
    r[3] = lower ? 1.0f : 0.0f;
  }
  return rows;
}

// Sampling weight of every texel, row-major: image.weight(x, y) * Omega(y), the texel's share of
// the integral of the nearest-texel radiance (docs/DESIGN.md §3). An all-zero image gets Omega(y) (uniform
// sphere) with a warning. Throws iblx::Error naming `builder` on an empty, mis-sized, negative or non-finite
// image.
inline std::vector<double> texelSamplingWeights(const EnvImage& image, const std::string& builder) {
  const int width = image.width, height = image.height;
  if (width <= 0 || height <= 0 || image.rgb.size() != 3 * image.texelCount())
    throw Error(builder + ": the environment image is empty or its pixel buffer does not match " +
                std::to_string(width) + " x " + std::to_string(height));
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    if (!std::isfinite(image.rgb[i]) || image.rgb[i] < 0.0f)
      throw Error(builder + ": texel " + std::to_string(i / 3) +
                  " is negative or not finite; sanitize the environment image first");
  }
  std::vector<double> weights(image.texelCount());
  bool allZero = true;
  for (int y = 0; y < height; ++y) {
    const double omega = latLongTexelSolidAngle(y, width, height);
    for (int x = 0; x < width; ++x) {
      const double w = image.weight(x, y) * omega;
      weights[image.index(x, y)] = w;
      allZero = allZero && w == 0.0;
    }
  }
  if (allZero) {
    warn(builder + ": the environment is black everywhere; sampling the sphere uniformly");
    for (int y = 0; y < height; ++y)
      std::fill_n(weights.begin() + std::ptrdiff_t(image.index(0, y)), width,
                  latLongTexelSolidAngle(y, width, height));
  }
  return weights;
}

}  // namespace iblx
