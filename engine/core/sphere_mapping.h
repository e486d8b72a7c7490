// The conventions of docs/DESIGN.md §3 written once: lat-long <-> direction, texel solid angles, camera pixels.
// shaders/lib/latlong.glsl is the GPU twin of this file; tests/sampling/sphere_mapping_test.cpp checks both
// agree with the design document.
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <numbers>
#include <optional>

namespace iblx {

inline constexpr double kPi = std::numbers::pi;

// u in [0,1) along the width, v in [0,1) down the height; phi = 2*pi*u, theta = pi*v from +Y.
inline glm::dvec3 latLongToDirection(glm::dvec2 uv) {
  const double phi = 2.0 * kPi * uv.x, theta = kPi * uv.y;
  return {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
}

// Inverse of latLongToDirection; theta from atan2 so it stays accurate at the poles.
inline glm::dvec2 directionToLatLong(glm::dvec3 w) {
  const double theta = std::atan2(std::hypot(w.x, w.z), w.y);
  double phi = std::atan2(w.z, w.x);
  if (phi < 0.0) phi += 2.0 * kPi;
  double u = phi / (2.0 * kPi);
  if (u >= 1.0) u = std::nextafter(1.0, 0.0);  // phi rounded up to 2 pi: the last column, as on the GPU
  return {u, theta / kPi};
}

// cos(a) - cos(b) = 2 sin((a + b) / 2) sin((b - a) / 2), without the cancellation of the plain difference
// when a and b are close (thin bands, the poles).
inline double cosDifference(double a, double b) {
  return 2.0 * std::sin(0.5 * (a + b)) * std::sin(0.5 * (b - a));
}
// cos(pi a) - cos(pi b) for latitudes given as v = theta / pi (docs/DESIGN.md §3), likewise.
inline double cosDifferenceOfV(double a, double b) {
  return 2.0 * std::sin(0.5 * kPi * (a + b)) * std::sin(0.5 * kPi * (b - a));
}

// Exact solid angle of any texel in row y of a width x height lat-long map: 2*pi/W * (cos(theta0) -
// cos(theta1)). Written as 2*sin((theta1+theta0)/2)*sin((theta1-theta0)/2) to avoid cancellation near the
// poles.
inline double latLongTexelSolidAngle(int y, int width, int height) {
  const double theta0 = kPi * y / height, theta1 = kPi * (y + 1) / height;
  return 2.0 * kPi / width * 2.0 * std::sin(0.5 * (theta1 + theta0)) * std::sin(0.5 * (theta1 - theta0));
}

// The default orthographic camera: looks down -Z at the unit sphere, which fills the image.
struct CameraRay {
  double x = 0.0, y = 0.0;  // image-plane coordinates; y in [-1,1], x in [-W/H, W/H]
};

inline CameraRay pixelToImagePlane(int i, int j, int width, int height) {
  const double aspect = double(width) / double(height);
  return {(2.0 * (i + 0.5) / width - 1.0) * aspect, 1.0 - 2.0 * (j + 0.5) / height};
}

// Normal of the unit sphere seen at image-plane point (x, y), or nothing for background pixels.
inline std::optional<glm::dvec3> sphereNormalAt(CameraRay p) {
  const double r2 = p.x * p.x + p.y * p.y;
  if (r2 >= 1.0) return std::nullopt;
  return glm::dvec3(p.x, p.y, std::sqrt(1.0 - r2));
}

// Rotation of the environment about +Y by `degrees`: world direction -> environment-map direction.
// A positive angle moves the map's features towards increasing phi as seen in the world.
inline glm::dvec3 worldToEnv(glm::dvec3 w, double degrees) {
  const double a = degrees * kPi / 180.0, c = std::cos(a), s = std::sin(a);
  return {c * w.x + s * w.z, w.y, -s * w.x + c * w.z};
}

}  // namespace iblx
