// Isotropic GGX / Trowbridge-Reitz microfacet terms in the local frame (n = +Z), shared by the "ggx" BRDF
// and the "ggx-vndf" sampler. Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces".
#ifndef IBLX_LIB_GGX
#define IBLX_LIB_GGX
#include "lib/constants.glsl"

// D(h) = alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2), written as 1 / (pi a^2 (|h_xy|^2/a^2 + h_z^2)^2),
// which stays accurate for alpha down to 1e-3 near the peak.
float ggxD(vec3 h, float alpha) {
  if (h.z <= 0.0) return 0.0;
  float e = dot(h.xy, h.xy) / (alpha * alpha) + h.z * h.z;
  return 1.0 / (kPi * alpha * alpha * e * e);
}

// Smith Lambda for GGX: (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2 (Heitz 2014, "Understanding the Masking-
// Shadowing Function in Microfacet-Based BRDFs", eq. 86).
float ggxLambda(vec3 w, float alpha) {
  float cos2 = w.z * w.z;
  if (cos2 <= 0.0) return 1e30;
  float tan2 = max(1.0 - cos2, 0.0) / cos2;
  return 0.5 * (-1.0 + sqrt(1.0 + alpha * alpha * tan2));
}

float ggxG1(vec3 w, float alpha) { return w.z > 0.0 ? 1.0 / (1.0 + ggxLambda(w, alpha)) : 0.0; }

// Height-correlated masking-shadowing (Heitz 2014, eq. 99).
float ggxG2(vec3 wi, vec3 wo, float alpha) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return 0.0;
  return 1.0 / (1.0 + ggxLambda(wi, alpha) + ggxLambda(wo, alpha));
}

// Schlick 1994 Fresnel approximation.
vec3 fresnelSchlick(vec3 f0, float cosTheta) {
  float m = clamp(1.0 - cosTheta, 0.0, 1.0);
  float m2 = m * m;
  return f0 + (1.0 - f0) * (m2 * m2 * m);
}
#endif
