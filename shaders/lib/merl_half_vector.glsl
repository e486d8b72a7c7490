// The half-vector parameterisation shared by the MERL BRDF techniques (engine/sampling/brdf/merl_sampling.h):
// u_theta = sqrt(theta_h / (pi/2)) (MERL's theta_h warp), phi_h = 2 pi u_phi; wi = reflect(wo about h).
#ifndef IBLX_LIB_MERL_HALF_VECTOR
#define IBLX_LIB_MERL_HALF_VECTOR
#include "lib/constants.glsl"

vec3 merlHalfVector(float uTheta, float phiH) {
  float thetaH = uTheta * uTheta * (0.5 * kPi);
  float sinThetaH = sin(thetaH);
  return vec3(sinThetaH * cos(phiH), sinThetaH * sin(phiH), cos(thetaH));
}

// u_theta of a half vector, with sin(theta_h) (theta_h from atan: accurate near the normal).
float merlUTheta(vec3 h, out float sinThetaH) {
  sinThetaH = length(h.xy);
  return sqrt(atan(sinThetaH, h.z) / (0.5 * kPi));
}

// p(wi) = p(u) / (2 pi^2 u_theta sin(theta_h)) / (4 |wo.h|): d omega_h = sin theta_h d theta_h d phi_h with
// d theta_h = pi u_theta d u_theta, d phi_h = 2 pi d u_phi; then Walter et al. 2007, eq. 14. 0 when degenerate.
float merlHalfVectorPdf(float pdfU, float uTheta, float sinThetaH, float woDotH) {
  float jacobian = 2.0 * kPi * kPi * uTheta * sinThetaH * 4.0 * abs(woDotH);
  return jacobian > 0.0 ? pdfU / jacobian : 0.0;
}

// The half vector that reflects wo into wi, in the upper hemisphere (the only one the techniques sample; a
// sampled h with wo.h < 0 reflects wo below the horizon, and normalize(wi + wo) is then -h). False when
// wi = -wo.
bool merlHalfVectorOf(vec3 wi, vec3 wo, out vec3 h) {
  h = wi + wo;
  float len2 = dot(h, h);
  if (!(len2 > 0.0)) return false;
  h *= inversesqrt(len2);
  if (h.z < 0.0) h = -h;
  return true;
}
#endif
