// Sequence "random": independent uniform points from a PCG hash of (pixel, sample index, seed, pair).
#include "lib/hash.glsl"

vec2 sequenceSample(uvec2 pixel, uint sampleIndex, uint seed, uint pair) {
  uvec4 h = pcg4d(uvec4(pixel, sampleIndex, seed));
  // Pairs 0 and 1 share one hash (its four outputs are independent); later pairs hash it again with the pair.
  if (pair >= 2u) h = pcg4d(h ^ uvec4(pair >> 1u));
  return (pair & 1u) == 0u ? vec2(uintToUnitFloat(h.x), uintToUnitFloat(h.y))
                           : vec2(uintToUnitFloat(h.z), uintToUnitFloat(h.w));
}
