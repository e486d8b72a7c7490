// The 2D Sobol sequence (the first dimension is the bit reversal of the index; the second has Pascal's
// triangle mod 2 as generator matrix, v_{k+1} = v_k ^ (v_k >> 1)) and Burley's hash-based nested uniform
// scrambling. Shared by the `sobol` and `cp-shared` sequences.
#ifndef IBLX_LIB_SOBOL
#define IBLX_LIB_SOBOL
// A fixed 32-step branch-free loop (it unrolls; SIMD lanes do not diverge).
uint sobolSecondDimension(uint index) {
  uint result = 0u;
  uint v = 1u << 31u;
  for (int bit = 0; bit < 32; ++bit) {
    result ^= v & (0u - ((index >> uint(bit)) & 1u));
    v ^= v >> 1u;
  }
  return result;
}

// Laine & Karras 2011 style hash permutation used by Burley 2020 (JCGT 9(4), listing 2) for nested uniform
// scrambling.
uint laineKarrasPermutation(uint x, uint seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// Owen scrambling of x read as a binary fraction (Burley 2020, listing 3).
uint nestedUniformScramble(uint x, uint seed) {
  return bitfieldReverse(laineKarrasPermutation(bitfieldReverse(x), seed));
}
#endif
