// BRDF technique "merl-thetah" for "merl": the simple baseline. A 1D float CDF over MERL's 90 theta_h bins
// (engine/sampling/brdf/merl_sampling.cpp builds it), u_theta uniform inside the bin, phi_h uniform, wi = reflect.
// Twin: MerlThetaHSampler.
#include "lib/table.glsl"
#include "lib/merl_half_vector.glsl"

IBLX_TABLE(merlThetaHCdf, 1);

const int kMerlThetaHCells = 90;

// Largest i with cdf[i] <= u (cdf[90] = 1 > u): a zero-width bin is never chosen. Constant trip count.
int merlThetaHBin(float u) { return tableSearchFloat(merlThetaHCdf, 0u, 0, kMerlThetaHCells, u); }

vec3 brdfSample(vec2 u, vec3 wo, out float pdf) {
  pdf = 0.0;
  if (wo.z <= 0.0) return vec3(0.0, 0.0, 1.0);
  int i = merlThetaHBin(u.x);
  float c0 = tableFloat(merlThetaHCdf, i), binProb = tableFloat(merlThetaHCdf, i + 1) - c0;
  float t = binProb > 0.0 ? clamp((u.x - c0) / binProb, 0.0, kOneMinusEpsilon) : 0.5;
  float uTheta = (float(i) + t) / float(kMerlThetaHCells);
  vec3 h = merlHalfVector(uTheta, kTwoPi * u.y);
  float woDotH = dot(wo, h);
  vec3 wi = 2.0 * woDotH * h - wo;
  pdf = merlHalfVectorPdf(binProb * float(kMerlThetaHCells), uTheta, length(h.xy), woDotH);
  return wi;
}

float brdfPdf(vec3 wi, vec3 wo) {
  vec3 h;
  if (wo.z <= 0.0 || !merlHalfVectorOf(wi, wo, h)) return 0.0;
  float sinThetaH;
  float uTheta = merlUTheta(h, sinThetaH);
  int i = clamp(int(uTheta * float(kMerlThetaHCells)), 0, kMerlThetaHCells - 1);
  float binProb = tableFloat(merlThetaHCdf, i + 1) - tableFloat(merlThetaHCdf, i);
  return merlHalfVectorPdf(binProb * float(kMerlThetaHCells), uTheta, sinThetaH, dot(wo, h));
}
