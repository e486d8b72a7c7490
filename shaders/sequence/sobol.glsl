// Sequence "sobol": the first two Sobol dimensions, Owen-scrambled and index-shuffled per pixel and per
// dimension pair (randomized QMC): every power-of-two prefix of one pair's points is a scrambled
// (0,m,2)-net, and the per-pair index shuffle decorrelates the pairs (padding, Burley 2020, "Practical
// Hash-based Owen Scrambling", JCGT 9(4), §5).
#include "lib/hash.glsl"
#include "lib/sobol.glsl"

vec2 sequenceSample(uvec2 pixel, uint sampleIndex, uint seed, uint pair) {
  // The pair enters the hash key, so each pair has its own shuffle (h.x) and scrambles (h.y, h.z).
  uvec4 h = pcg4d(uvec4(pixel, seed, 0x5eed5eedu ^ (pair * 0x9e3779b9u)));
  uint index = nestedUniformScramble(sampleIndex, h.x);
  uint x = nestedUniformScramble(bitfieldReverse(index), h.y);
  uint y = nestedUniformScramble(sobolSecondDimension(index), h.z);
  return vec2(uintToUnitFloat(x), uintToUnitFloat(y));
}
