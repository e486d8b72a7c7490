// Environment-technique role. Directions are unit vectors in the environment frame (the map's own frame);
// n is the shading normal in that frame (techniques that ignore it, such as env-cdf, may).
#ifndef IBLX_INTERFACE_ENV_SAMPLER
#define IBLX_INTERFACE_ENV_SAMPLER
// pdf: the exact density w.r.t. solid angle of the direction returned; 0 = the sample contributes nothing.
// radiance: the environment radiance the estimator must use for this sample: envRadiance(direction), or, for
// texel-based techniques, the radiance of the texel actually sampled (the same value except when float rounding
// puts the direction on a neighbouring texel's side of an edge; using the sampled texel keeps radiance / pdf
// exactly constant per texel).
vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance);
// The same density for any direction (used by MIS).
float envPdf(vec3 wi, vec3 n);
#endif
