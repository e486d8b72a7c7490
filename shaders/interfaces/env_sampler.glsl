// Environment-technique role. Directions are unit vectors in the environment frame (the map's own frame);
// n is the shading normal in that frame (techniques that ignore it, such as env-cdf, may).
#ifndef IBLX_INTERFACE_ENV_SAMPLER
#define IBLX_INTERFACE_ENV_SAMPLER
// pdf: the exact density w.r.t. solid angle of the direction returned; 0 = the sample contributes nothing.
vec3 envSample(vec2 u, vec3 n, out float pdf);
// The same density for any direction (used by MIS).
float envPdf(vec3 wi, vec3 n);
#endif
