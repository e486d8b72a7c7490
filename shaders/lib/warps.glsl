// Closed-form warps of the unit square (sample / pdf pairs), GPU side.
#ifndef IBLX_LIB_WARPS
#define IBLX_LIB_WARPS
#include "lib/constants.glsl"

// Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square": concentric square -> unit disk.
vec2 squareToConcentricDisk(vec2 u) {
  vec2 o = 2.0 * u - 1.0;
  if (o.x == 0.0 && o.y == 0.0) return vec2(0.0);
  float r, theta;
  if (abs(o.x) > abs(o.y)) {
    r = o.x;
    theta = 0.25 * kPi * (o.y / o.x);
  } else {
    r = o.y;
    theta = 0.5 * kPi - 0.25 * kPi * (o.x / o.y);
  }
  return r * vec2(cos(theta), sin(theta));
}

// Density cos(theta)/pi w.r.t. solid angle, local frame (+Z up); Malley's method.
vec3 squareToCosineHemisphere(vec2 u) {
  vec2 d = squareToConcentricDisk(u);
  return vec3(d, sqrt(max(0.0, 1.0 - dot(d, d))));
}
float cosineHemispherePdf(float cosTheta) { return max(cosTheta, 0.0) * kInvPi; }

// Density 1/(4 pi) w.r.t. solid angle.
vec3 squareToUniformSphere(vec2 u) {
  float z = 1.0 - 2.0 * u.x;
  float r = sqrt(max(0.0, 1.0 - z * z));
  float phi = kTwoPi * u.y;
  return vec3(r * cos(phi), r * sin(phi), z);
}
const float kUniformSpherePdf = 0.25 * kInvPi;

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1): t, b from n.
void orthonormalBasis(vec3 n, out vec3 t, out vec3 b) {
  float sign = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (sign + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = vec3(c, sign + n.y * n.y * a, -n.y);
}
#endif
