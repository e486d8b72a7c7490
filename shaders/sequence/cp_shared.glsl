// Sequence "cp-shared": one point set shared by every pixel, the unscrambled 2D Sobol sequence (every power-of-two
// prefix is a (0,m,2)-net), with a per-pixel Cranley-Patterson rotation: u = fract(p_i + shift(pixel, seed)).
// The set is the same table for all pixels, generated here bit-exactly instead of read from a buffer; the random
// toroidal shift makes every point uniform, so estimates stay unbiased (Cranley & Patterson 1976). Unlike
// `sobol`'s per-pixel Owen scrambling, the shift keeps the set's structure, so the comparison shows what a warp's
// continuity is worth on one fixed low-discrepancy pattern. Pairs after the first read the same set in an
// order shuffled once per pair (the same for every pixel) and get their own shift: without the shuffle, pair 1
// would be pair 0 moved by a constant.
#include "lib/hash.glsl"
#include "lib/sobol.glsl"

vec2 sequenceSample(uvec2 pixel, uint sampleIndex, uint seed, uint pair) {
  uvec4 h = pcg4d(uvec4(pixel, seed, 0xc0ffee11u ^ (pair * 0x9e3779b9u)));
  uint index = pair == 0u ? sampleIndex : nestedUniformScramble(sampleIndex, pcg4d(uvec4(pair, 0x5a3ed5u, 0u, 0u)).x);
  // Shift in 32-bit fixed point: the addition wraps modulo 1 exactly.
  uint x = bitfieldReverse(index) + h.x;
  uint y = sobolSecondDimension(index) + h.y;
  return vec2(uintToUnitFloat(x), uintToUnitFloat(y));
}
