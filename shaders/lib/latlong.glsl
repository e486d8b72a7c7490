// GPU twin of engine/sampling/sphere_mapping.h and latlong_texel.h: lat-long <-> direction (DESIGN §3),
// the texel of a direction, the area-preserving map from [0,1)^2 onto one texel, and the radiance lookup.
#ifndef IBLX_LIB_LATLONG
#define IBLX_LIB_LATLONG
#include "lib/constants.glsl"
#include "lib/frame_resources.glsl"

ivec2 envSize() { return ivec2(frame.envWidth, frame.envHeight); }

// theta from atan(length(xz), y): accurate at the poles, unlike acos(y).
vec2 directionToLatLong(vec3 w) {
  float theta = atan(length(w.xz), w.y);
  float phi = atan(w.z, w.x);
  if (phi < 0.0) phi += kTwoPi;
  return vec2(phi / kTwoPi, theta / kPi);
}

ivec2 directionToTexel(vec3 w) {
  ivec2 size = envSize();
  return clamp(ivec2(directionToLatLong(w) * vec2(size)), ivec2(0), size - 1);
}

// Maps t in [0,1)^2 onto texel `texel` with constant density w.r.t. solid angle: phi linear in t.x,
// cos(theta) linear in t.y. cos(theta) is formed from sin^2(theta/2) (upper half) or cos^2(theta/2)
// (lower half) so that rows next to either pole keep full float precision.
vec3 texelToDirection(ivec2 texel, vec2 t) {
  ivec2 size = envSize();
  float phi = kTwoPi * (float(texel.x) + t.x) / float(size.x);
  float halfTheta0 = 0.5 * kPi * float(texel.y) / float(size.y);
  float halfTheta1 = 0.5 * kPi * float(texel.y + 1) / float(size.y);
  float cosTheta, sinTheta;
  if (2 * texel.y < size.y) {
    float s0 = sin(halfTheta0), s1 = sin(halfTheta1);
    float s = mix(s0 * s0, s1 * s1, t.y);  // sin^2(theta/2) = (1 - cos(theta)) / 2
    cosTheta = 1.0 - 2.0 * s;
    sinTheta = 2.0 * sqrt(max(s * (1.0 - s), 0.0));
  } else {
    float c0 = cos(halfTheta0), c1 = cos(halfTheta1);
    float c = mix(c0 * c0, c1 * c1, t.y);  // cos^2(theta/2) = (1 + cos(theta)) / 2
    cosTheta = 2.0 * c - 1.0;
    sinTheta = 2.0 * sqrt(max(c * (1.0 - c), 0.0));
  }
  return vec3(sinTheta * cos(phi), cosTheta, sinTheta * sin(phi));
}

vec3 envTexelRadiance(ivec2 texel) {
  uint i = 3u * (uint(texel.y) * frame.envWidth + uint(texel.x));
  return vec3(envRgb[i], envRgb[i + 1u], envRgb[i + 2u]);
}

// Nearest-texel radiance in environment-frame direction w.
vec3 envRadiance(vec3 w) { return envTexelRadiance(directionToTexel(w)); }

float texelSolidAngle(ivec2 texel) { return envRowSolidAngle[texel.y]; }
#endif
