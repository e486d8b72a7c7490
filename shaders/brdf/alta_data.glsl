// BRDF of an ALTA data file (engine/io/alta_data.h) on its grid (engine/sampling/brdf/alta_grid.h): the direction
// pair's coordinates in the grid's parametrisation (ALTA_PARAM_IN, one of four dimensions or fewer; the forward
// maps are lib/alta_params.glsl's), azimuths folded into their axes (ALTA_FOLD<d>), then a
// multilinear lookup over the (possibly uneven) axes; values stored as f cos(theta_L) (ALTA_COSINE) are
// divided by the cosine. GPU twin of evalAltaGrid (engine/sampling/brdf/alta_grid.cpp). Every loop has a
// compile-time trip count and is unrolled: lavapipe caps the loop iterations of an invocation (the reference
// kernel evaluates the BRDF many times per invocation).
#extension GL_EXT_control_flow_attributes : require
#include "lib/table.glsl"
#include "lib/constants.glsl"
#include "lib/alta_params.glsl"

// The axes (ALTA_AT_AXIS<d>: ALTA_N<d> increasing node coordinates), then the values, planar by channel.
IBLX_TABLE(altaData, 1);

float altaAt(uint i) { return tableFloat(altaData, i); }

float altaPositiveMod(float x, float period) { return x - period * floor(x / period); }

float altaFold(float x, int rule, float axisMin) {
  if (rule == 1) return axisMin + altaPositiveMod(x - axisMin, 2.0 * kPi);  // a whole turn
  if (rule == 2) return altaPositiveMod(x, kPi);                           // reciprocity
  if (rule == 3) {                                                          // mirror
    float t = altaPositiveMod(x, 2.0 * kPi);
    return t > kPi ? 2.0 * kPi - t : t;
  }
  if (rule == 4) {  // reciprocity, then mirror
    float t = altaPositiveMod(x, kPi);
    return t > 0.5 * kPi ? kPi - t : t;
  }
  return x;
}

vec4 altaCoordinates(vec3 wi, vec3 wo) {
  float x[6];
  altaParamCoordinates(wi, wo, x);
  return vec4(x[0], x[1], x[2], x[3]);
}

// The lower node of x on an axis and the upper node's weight, x folded and clamped first.
void altaAxis(uint at, uint n, uint steps, int rule, float x, out uint lower, out float weight) {
  float lo = altaAt(at), hi = altaAt(at + n - 1u);
  x = clamp(altaFold(x, rule, lo), lo, hi);
  lower = 0u;
  weight = 0.0;
  if (n < 2u) return;
  uint len = n - 1u;
  [[unroll]] for (uint step = 0u; step < steps; ++step) {  // the largest node <= x, below the last
    uint halfLen = len >> 1u;
    lower = altaAt(at + lower + halfLen) <= x ? lower + halfLen : lower;
    len -= halfLen;
  }
  float a = altaAt(at + lower), b = altaAt(at + lower + 1u);
  weight = b > a ? clamp((x - a) / (b - a), 0.0, 1.0) : 0.0;
}

vec3 brdfEval(vec3 wi, vec3 wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
  vec4 k = altaCoordinates(wi, wo);
  const uvec4 n = uvec4(ALTA_N0, ALTA_N1, ALTA_N2, ALTA_N3);
  uvec4 lower;
  vec4 weight;
  altaAxis(ALTA_AT_AXIS0, ALTA_N0, ALTA_STEPS0, ALTA_FOLD0, k.x, lower.x, weight.x);
  altaAxis(ALTA_AT_AXIS1, ALTA_N1, ALTA_STEPS1, ALTA_FOLD1, k.y, lower.y, weight.y);
  altaAxis(ALTA_AT_AXIS2, ALTA_N2, ALTA_STEPS2, ALTA_FOLD2, k.z, lower.z, weight.z);
  altaAxis(ALTA_AT_AXIS3, ALTA_N3, ALTA_STEPS3, ALTA_FOLD3, k.w, lower.w, weight.w);
  vec3 value = vec3(0.0);
  [[unroll]] for (int corner = 0; corner < (1 << ALTA_DIMS); ++corner) {
    float w = 1.0;
    uint index = 0u;
    [[unroll]] for (int d = 0; d < ALTA_DIMS; ++d) {
      bool upper = ((corner >> d) & 1) != 0;
      w *= upper ? weight[d] : 1.0 - weight[d];
      index = index * n[d] + min(lower[d] + (upper ? 1u : 0u), n[d] - 1u);
    }
    if (w > 0.0)
      value += w * vec3(altaAt(ALTA_AT_RGB + index), altaAt(ALTA_AT_RGB + ALTA_NODES + index),
                        altaAt(ALTA_AT_RGB + 2u * ALTA_NODES + index));
  }
#if ALTA_COSINE
  value /= wi.z;
#endif
  return max(value, vec3(0.0));
}
