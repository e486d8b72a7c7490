// Sequence role: where the uniform 2D points a strategy consumes come from.
#ifndef IBLX_INTERFACE_SEQUENCE
#define IBLX_INTERFACE_SEQUENCE
// Point sampleIndex of the 2D dimension pair `pair` (0, 1, 2, ...) of pixel `pixel` under `seed`; every
// component in [0,1). Pairs are padded (Burley 2020, "Practical Hash-based Owen Scrambling", §5): each pair is
// its own 2D sequence with its own randomization, so each pair alone has the sequence's stratification (for
// sobol every pair is a scrambled (0,2)-sequence) and distinct pairs are independent of each other. Pair 0
// is the point the sample overlay shows as the sequence's point.
vec2 sequenceSample(uvec2 pixel, uint sampleIndex, uint seed, uint pair);
#endif
