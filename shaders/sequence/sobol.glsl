// Sequence "sobol": the first two Sobol dimensions, Owen-scrambled and index-shuffled per pixel
// (randomized QMC): every power-of-two prefix of a pixel's points is a scrambled (0,m,2)-net.
// Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4).
#include "lib/hash.glsl"
#include "lib/sobol.glsl"

// Laine & Karras 2011 style hash permutation used by Burley 2020 for nested uniform scrambling.
uint laineKarrasPermutation(uint x, uint seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

uint nestedUniformScramble(uint x, uint seed) {
  return bitfieldReverse(laineKarrasPermutation(bitfieldReverse(x), seed));
}

vec2 sequenceSample(uvec2 pixel, uint sampleIndex, uint seed) {
  uvec4 h = pcg4d(uvec4(pixel, seed, 0x5eed5eedu));
  uint index = nestedUniformScramble(sampleIndex, h.x);
  uint x = nestedUniformScramble(bitfieldReverse(index), h.y);
  uint y = nestedUniformScramble(sobolSecondDimension(index), h.z);
  return vec2(uintToUnitFloat(x), uintToUnitFloat(y));
}
