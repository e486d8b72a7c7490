// The second dimension of the Sobol sequence (the first is the bit reversal of the index): generator matrix =
// Pascal's triangle mod 2 (v_{k+1} = v_k ^ (v_k >> 1)). Shared by the `sobol` and `cp-shared` sequences.
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
#endif
