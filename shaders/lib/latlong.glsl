// GPU twin of engine/sampling/sphere_mapping.h and latlong_texel.h: lat-long <-> direction (docs/DESIGN.md §3),
// the texel of a direction, the area-preserving map from [0,1)^2 onto one texel, and the radiance lookup.
#ifndef IBLX_LIB_LATLONG
#define IBLX_LIB_LATLONG
#include "lib/constants.glsl"
#include "lib/frame_resources.glsl"

ivec2 envSize() { return ivec2(frame.envWidth, frame.envHeight); }

// theta from atan(length(xz), y): accurate at the poles, unlike acos(y).
vec2 directionToLatLong(vec3 w) {
  float theta = atan(length(w.xz), w.y);
  float phi = (w.x == 0.0 && w.z == 0.0) ? 0.0 : atan(w.z, w.x);  // atan(0, 0) is undefined in GLSL
  if (phi < 0.0) phi += kTwoPi;
  return vec2(phi / kTwoPi, theta / kPi);
}

ivec2 directionToTexel(vec3 w) {
  ivec2 size = envSize();
  return clamp(ivec2(directionToLatLong(w) * vec2(size)), ivec2(0), size - 1);
}

// Maps t in [0,1)^2 onto texel `texel` with constant density w.r.t. solid angle: phi linear in t.x,
// cos(theta) linear in t.y. cos(theta) comes from a = sin^2(theta/2) (upper half) or cos^2(theta/2) (lower
// half), linear in t.y between the row's tabulated edge values, so rows next to either pole keep full float
// precision and no trigonometry is needed for theta.
vec3 texelToDirection(ivec2 texel, vec2 t) {
  vec4 row = tableVec4(envRows, texel.y);
  float a = mix(row.y, row.z, t.y);
  float cosTheta = row.w > 0.5 ? 2.0 * a - 1.0 : 1.0 - 2.0 * a;
  float sinTheta = 2.0 * sqrt(max(a * (1.0 - a), 0.0));
  float phi = kTwoPi * (float(texel.x) + t.x) / float(frame.envWidth);
  return vec3(sinTheta * cos(phi), cosTheta, sinTheta * sin(phi));
}

// Inverse of texelToDirection's t for a direction inside (or on the border of) `texel`, clamped to [0,1]^2.
vec2 directionToTexelOffset(vec3 w, ivec2 texel) {
  float tx = directionToLatLong(w).x * float(frame.envWidth) - float(texel.x);
  if (tx < -0.5 * float(frame.envWidth)) tx += float(frame.envWidth);  // phi wrapped to 0 on the last column
  vec4 row = tableVec4(envRows, texel.y);
  float cosTheta = w.y / length(w);
  float a = row.w > 0.5 ? 0.5 * (1.0 + cosTheta) : 0.5 * (1.0 - cosTheta);
  float ty = row.z != row.y ? (a - row.y) / (row.z - row.y) : 0.5;
  return clamp(vec2(tx, ty), vec2(0.0), vec2(1.0));
}

vec3 tableRgb(usamplerBuffer table, uint i) {
  return vec3(tableFloat(table, i), tableFloat(table, i + 1u), tableFloat(table, i + 2u));
}

vec3 envTexelRadiance(ivec2 texel) {
  uint t = uint(texel.y) * frame.envWidth + uint(texel.x);
#if ENV_RADIANCE_CHUNKS > 1
  uint chunk = t / ENV_TEXELS_PER_CHUNK;
  uint i = 3u * (t - chunk * ENV_TEXELS_PER_CHUNK);
  if (chunk == 1u) return tableRgb(envRgb1, i);
#if ENV_RADIANCE_CHUNKS > 2
  if (chunk == 2u) return tableRgb(envRgb2, i);
#endif
#if ENV_RADIANCE_CHUNKS > 3
  if (chunk == 3u) return tableRgb(envRgb3, i);
#endif
#else
  uint i = 3u * t;
#endif
  return tableRgb(envRgb, i);
}

// Nearest-texel radiance in environment-frame direction w.
vec3 envRadiance(vec3 w) { return envTexelRadiance(directionToTexel(w)); }

float texelSolidAngle(ivec2 texel) { return tableVec4(envRows, texel.y).x; }
#endif
