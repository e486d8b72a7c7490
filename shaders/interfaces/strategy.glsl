// Strategy role: combines the techniques into one estimate of Lo for one sample of a pixel.
#ifndef IBLX_INTERFACE_STRATEGY
#define IBLX_INTERFACE_STRATEGY
#include "lib/shading.glsl"
// Which sample of which pixel is being estimated. A strategy reads its uniform numbers through samplePair, one
// dimension pair per 2D point it consumes (the env technique's point, the BRDF technique's, each RIS
// candidate's, ...), never from a hash of its own: under sobol every pair is then a (0,2)-sequence.
struct SamplePoint {
  uvec2 pixel;
  uint index;  // in the pixel's sequence
  uint seed;
};
vec2 samplePair(SamplePoint p, uint pair) { return sequenceSample(p.pixel, p.index, p.seed, pair); }

// Once per shading point and dispatch, before its samples: per-pixel tables of a strategy (the product
// strategies' node weights); empty for the others.
void prepareStrategy(Shading s);
// One Monte Carlo estimate of the integral of docs/DESIGN.md §1 at the shading point s.
// Every strategy also describes each direction it draws through lib/sample_record.glsl's RECORD_DRAW and
// RECORD_WEIGHT (empty unless the kernel records samples): which technique role drew it from which 2D point,
// that technique's pdf, and the weight with contribution = radiance * weight.
vec3 estimateRadiance(SamplePoint p, Shading s);
#endif
