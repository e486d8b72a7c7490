// BRDF technique "cosine": cosine-weighted hemisphere (exact for Lambert; applies to every BRDF).
#include "lib/warps.glsl"

vec3 brdfSample(vec2 u, vec3 wo, out float pdf) {
  vec3 wi = squareToCosineHemisphere(u);
  pdf = cosineHemispherePdf(wi.z);
  return wi;
}

float brdfPdf(vec3 wi, vec3 wo) { return cosineHemispherePdf(wi.z); }
