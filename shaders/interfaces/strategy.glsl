// Strategy role: combines the techniques into one estimate of Lo for one 2D sample u.
#ifndef IBLX_INTERFACE_STRATEGY
#define IBLX_INTERFACE_STRATEGY
#include "lib/shading.glsl"
// One Monte Carlo estimate of the integral of DESIGN §1 at the shading point s. u is the sequence's 2D point
// (stratified for sobol); uPadding two more uniform numbers, independent of u (a hash; strategies that need
// more than one 2D point, such as ris, use it; the compiler drops it elsewhere).
// Every strategy also describes the sample it draws through lib/sample_record.glsl's RECORD_DRAW and
// RECORD_WEIGHT (empty unless the kernel records samples): which technique role drew the direction, that
// technique's pdf, and the weight with estimate = radiance * weight.
vec3 estimateRadiance(vec2 u, vec2 uPadding, Shading s);
#endif
