// Sequence role: where the uniform sample u in [0,1)^2 comes from.
#ifndef IBLX_INTERFACE_SEQUENCE
#define IBLX_INTERFACE_SEQUENCE
// The sampleIndex-th 2D point of pixel `pixel` under `seed`; every component in [0,1).
vec2 sequenceSample(uvec2 pixel, uint sampleIndex, uint seed);
#endif
