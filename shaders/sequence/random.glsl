// Sequence "random": independent uniform points from a PCG hash of (pixel, sample index, seed).
#include "lib/hash.glsl"

vec2 sequenceSample(uvec2 pixel, uint sampleIndex, uint seed) {
  uvec4 h = pcg4d(uvec4(pixel, sampleIndex, seed));
  return vec2(uintToUnitFloat(h.x), uintToUnitFloat(h.y));
}
