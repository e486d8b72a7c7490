// Integer hashes for GPU random numbers.
#ifndef IBLX_LIB_HASH
#define IBLX_LIB_HASH
// Jarzynski & Olano 2020, "Hash Functions for GPU Rendering", JCGT 9(3): pcg4d.
uvec4 pcg4d(uvec4 v) {
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  v ^= v >> 16u;
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  return v;
}
// 24 random bits -> [0,1): every value exactly representable, never 1.
float uintToUnitFloat(uint x) { return float(x >> 8u) * (1.0 / 16777216.0); }
#endif
