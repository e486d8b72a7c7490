// Env technique "env-cdf": marginal (rows) / conditional (columns) piecewise-constant CDFs over texels,
// built in double by engine/sampling/env_cdf.cpp and stored normalised as float. The pdf is the probability of
// the bin actually sampled (the float CDF difference) divided by the texel's exact solid angle; inside a texel
// the direction is uniform in solid angle, so radiance/pdf is constant per texel.
// Continuous in u.x within a row; discontinuous across row boundaries.
#include "lib/latlong.glsl"

// cdf[0 .. H]: marginal over rows; then per row y, cdf[H+1 + y*(W+1) .. + W]: conditional over columns.
layout(std430, set = 2, binding = 0) readonly buffer EnvCdfData { float envCdf[]; };

// Index i of the bin with cdf[base+i] <= u < cdf[base+i+1] among n bins (cdf[base+n] = 1 > u):
// the first entry above u, minus one, so zero-width bins are never chosen.
int envCdfFindBin(uint base, int n, float u) {
  int lo = 1, hi = n;
  while (lo < hi) {
    int mid = (lo + hi) >> 1;
    if (envCdf[base + uint(mid)] > u) hi = mid; else lo = mid + 1;
  }
  return lo - 1;
}

uint envCdfRowBase(int y) { return frame.envHeight + 1u + uint(y) * (frame.envWidth + 1u); }

vec3 envSample(vec2 u, vec3 n, out float pdf) {
  int H = int(frame.envHeight), W = int(frame.envWidth);
  int y = envCdfFindBin(0u, H, u.y);
  float c0 = envCdf[y], rowProb = envCdf[y + 1] - c0;
  float ty = clamp((u.y - c0) / rowProb, 0.0, kOneMinusEpsilon);  // rowProb > 0: the bin was chosen
  uint base = envCdfRowBase(y);
  int x = envCdfFindBin(base, W, u.x);
  float d0 = envCdf[base + uint(x)], colProb = envCdf[base + uint(x) + 1u] - d0;
  float tx = clamp((u.x - d0) / colProb, 0.0, kOneMinusEpsilon);
  ivec2 texel = ivec2(x, y);
  float solidAngle = texelSolidAngle(texel);
  pdf = solidAngle > 0.0 ? rowProb * colProb / solidAngle : 0.0;
  return texelToDirection(texel, vec2(tx, ty));
}

float envPdf(vec3 wi, vec3 n) {
  ivec2 texel = directionToTexel(wi);
  float rowProb = envCdf[texel.y + 1] - envCdf[texel.y];
  uint base = envCdfRowBase(texel.y) + uint(texel.x);
  float colProb = envCdf[base + 1u] - envCdf[base];
  float solidAngle = texelSolidAngle(texel);
  return solidAngle > 0.0 ? rowProb * colProb / solidAngle : 0.0;
}
