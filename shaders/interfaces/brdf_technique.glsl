// BRDF-technique role: sampling of wi given wo, local frame (n = +Z).
#ifndef IBLX_INTERFACE_BRDF_SAMPLER
#define IBLX_INTERFACE_BRDF_SAMPLER
// pdf: exact density w.r.t. solid angle of wi; 0 = the sample contributes nothing. wi may point below the
// horizon (then f*cos = 0 and the sample contributes nothing, but its pdf is still the true density).
vec3 brdfSample(vec2 u, vec3 wo, out float pdf);
// The same density for any wi (used by MIS).
float brdfPdf(vec3 wi, vec3 wo);
#endif
