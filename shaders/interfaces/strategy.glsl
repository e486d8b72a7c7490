// Strategy role: combines the techniques into one estimate of Lo for one 2D sample u.
#ifndef IBLX_INTERFACE_STRATEGY
#define IBLX_INTERFACE_STRATEGY
#include "lib/shading.glsl"
// One Monte Carlo estimate of the integral of DESIGN §1 at the shading point s.
vec3 estimateRadiance(vec2 u, Shading s);
#endif
