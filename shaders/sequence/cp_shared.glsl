// Sequence "cp-shared": one point set shared by every pixel, the unscrambled 2D Sobol sequence (every power-of-two
// prefix is a (0,m,2)-net), with a per-pixel Cranley-Patterson rotation: u = fract(p_i + shift(pixel, seed)).
// The set is the same table for all pixels, generated here bit-exactly instead of read from a buffer; the random
// toroidal shift makes every point uniform, so estimates stay unbiased (Cranley & Patterson 1976). Unlike
// `sobol`'s per-pixel Owen scrambling, the shift keeps the set's structure, so the comparison shows what a warp's
// continuity is worth on one fixed low-discrepancy pattern.
#include "lib/hash.glsl"
#include "lib/sobol.glsl"

vec2 sequenceSample(uvec2 pixel, uint sampleIndex, uint seed) {
  uvec4 h = pcg4d(uvec4(pixel, seed, 0xc0ffee11u));
  // Shift in 32-bit fixed point: the addition wraps modulo 1 exactly.
  uint x = bitfieldReverse(sampleIndex) + h.x;
  uint y = sobolSecondDimension(sampleIndex) + h.y;
  return vec2(uintToUnitFloat(x), uintToUnitFloat(y));
}
