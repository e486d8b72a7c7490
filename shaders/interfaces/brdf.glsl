// BRDF role: evaluation in the local shading frame (n = +Z, t = +X, b = +Y), in 1/sr, without the cosine.
#ifndef IBLX_INTERFACE_BRDF
#define IBLX_INTERFACE_BRDF
vec3 brdfEval(vec3 wi, vec3 wo);
#endif
