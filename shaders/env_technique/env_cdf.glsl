// Env technique "env-cdf": marginal (rows) / conditional (columns) piecewise-constant CDFs over texels,
// built in double by engine/sampling/env/env_cdf.cpp and stored normalised as float. The pdf is the probability of
// the bin actually sampled (the float CDF difference) divided by the texel's exact solid angle; inside a texel
// the direction is uniform in solid angle, so radiance/pdf is constant per texel.
// Continuous in u.x within a row; discontinuous across row boundaries.
#include "lib/table.glsl"
#include "lib/latlong.glsl"

// cdf[0 .. H]: marginal over rows; then per row y, cdf[H+1 + y*(W+1) .. + W]: conditional over columns.
IBLX_TABLE(envCdf, 1);
// Guide cells (EnvCdfData in engine/sampling/env/env_cdf.h): the marginal's ENV_CDF_ROW_GUIDE_SIZE cells, then
// ENV_CDF_COLUMN_GUIDE_SIZE cells per row; each packs lo | hi << 16, the range of bins its u values fall in.
IBLX_TABLE(envCdfGuide, 1);

// The largest i in [lo, hi] of guide cell `cell` with cdf[base + i] <= u, i.e. cdf[i] <= u < cdf[i+1], so a
// zero-width bin is never chosen. The search runs only over the cell's bins: no step when the cell holds one.
int envCdfFindBin(uint base, uint cell, float u) {
  uint range = tableUint(envCdfGuide, cell);
  int lo = int(range & 0xffffu);
  return tableSearchFloat(envCdf, base, lo, int(range >> 16u) - lo + 1, u);
}

uint envCdfRowBase(int y) { return frame.envHeight + 1u + uint(y) * (frame.envWidth + 1u); }

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  // u * G is exact (G a power of two) and < G for u < 1; the min() only guards against bad input.
  const uint rowCells = ENV_CDF_ROW_GUIDE_SIZE, columnCells = ENV_CDF_COLUMN_GUIDE_SIZE;
  int y = envCdfFindBin(0u, min(uint(u.y * float(rowCells)), rowCells - 1u), u.y);
  float c0 = tableFloat(envCdf, y), rowProb = tableFloat(envCdf, y + 1) - c0;
  uint base = envCdfRowBase(y);
  uint column = min(uint(u.x * float(columnCells)), columnCells - 1u);
  int x = envCdfFindBin(base, rowCells + uint(y) * columnCells + column, u.x);
  float d0 = tableFloat(envCdf, base + uint(x)), colProb = tableFloat(envCdf, base + uint(x) + 1u) - d0;
  // rowProb, colProb > 0: the search never returns a zero-width bin; the guards keep the code total.
  float ty = rowProb > 0.0 ? clamp((u.y - c0) / rowProb, 0.0, kOneMinusEpsilon) : 0.5;
  float tx = colProb > 0.0 ? clamp((u.x - d0) / colProb, 0.0, kOneMinusEpsilon) : 0.5;
  ivec2 texel = ivec2(x, y);
  float solidAngle = texelSolidAngle(texel);
  pdf = solidAngle > 0.0 ? rowProb * colProb / solidAngle : 0.0;
  radiance = envTexelRadiance(texel);
  return texelToDirection(texel, vec2(tx, ty));
}

float envPdf(vec3 wi, vec3 n) {
  ivec2 texel = directionToTexel(wi);
  float rowProb = tableFloat(envCdf, texel.y + 1) - tableFloat(envCdf, texel.y);
  uint base = envCdfRowBase(texel.y) + uint(texel.x);
  float colProb = tableFloat(envCdf, base + 1u) - tableFloat(envCdf, base);
  float solidAngle = texelSolidAngle(texel);
  return solidAngle > 0.0 ? rowProb * colProb / solidAngle : 0.0;
}
