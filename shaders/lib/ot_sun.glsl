// GPU twin of OtSunSplit (engine/sampling/env/env_ot_sun.h): the OT techniques sample the mixture
// p(w) = share * pSun(w) + (1 - share) * pOt(w), the sun part (the capped texels' excess weight) by a CDF over
// its texels and uniformly in solid angle inside the texel chosen. Bindings 4-6 of set 2 follow the quad map's
// 0-3 (lib/quad_grid_map.glsl); OT_SUN_SHARE_BITS is the float share's bit pattern, so it is exact.
#ifndef IBLX_LIB_OT_SUN
#define IBLX_LIB_OT_SUN
#include "lib/table.glsl"
#include "lib/constants.glsl"
#include "lib/latlong.glsl"

IBLX_TABLE(otSunTexel, 1);  // ascending y*W+x
IBLX_TABLE(otSunCdf, 1);
IBLX_TABLE(otSunRowFirst, 1);  // H+1 entries

float otSunShare() { return uintBitsToFloat(OT_SUN_SHARE_BITS); }

// pSun per unit solid angle on texel t: its probability over its solid angle, 0 when it is not a sun texel.
float otSunTexelPdf(ivec2 t) {
  uint lo = tableUint(otSunRowFirst, t.y), len = tableUint(otSunRowFirst, t.y + 1) - lo;
  if (len == 0u) return 0.0;
  uint target = uint(t.y) * frame.envWidth + uint(t.x);
  // The largest entry <= target among the row's sun texels.
  lo = tableSearchUint(otSunTexel, lo, len, target);
  if (tableUint(otSunTexel, lo) != target) return 0.0;
  float prob = tableFloat(otSunCdf, lo + 1u) - tableFloat(otSunCdf, lo), solidAngle = texelSolidAngle(t);
  return solidAngle > 0.0 ? prob / solidAngle : 0.0;
}

// A direction of the sun part: u.x picks the texel (the largest k with cdf[k] <= u.x, so a zero-width entry is
// never chosen) and, remapped, places the direction across it; u.y along it. Returns the texel and its pSun.
vec3 otSunSample(vec2 u, out ivec2 texel, out float pdf) {
  int lo = tableSearchFloat(otSunCdf, 0u, 0, OT_SUN_TEXELS, u.x);
  float c0 = tableFloat(otSunCdf, lo), width = tableFloat(otSunCdf, lo + 1) - c0;
  float s = width > 0.0 ? clamp((u.x - c0) / width, 0.0, kOneMinusEpsilon) : 0.5;
  uint index = tableUint(otSunTexel, lo);
  texel = ivec2(index % frame.envWidth, index / frame.envWidth);
  float solidAngle = texelSolidAngle(texel);
  pdf = solidAngle > 0.0 ? width / solidAngle : 0.0;
  return texelToDirection(texel, vec2(s, u.y));
}

// Splits u between the parts: true for the sun part. u.y is remapped to [0, 1) inside the part chosen.
bool otSunChoose(inout vec2 u) {
  float share = otSunShare();
  if (u.y < share) {
    u.y = clamp(u.y / share, 0.0, kOneMinusEpsilon);
    return true;
  }
  u.y = share > 0.0 ? clamp((u.y - share) / (1.0 - share), 0.0, kOneMinusEpsilon) : u.y;
  return false;
}

// The mixture's pdf per unit solid angle from both parts' pdfs at the same direction.
float otSunMixture(float pSun, float pOt) { return otSunShare() * pSun + (1.0 - otSunShare()) * pOt; }
#endif
