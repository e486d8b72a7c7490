// BRDF technique "ggx-vndf" for the "ggx" BRDF: a mixture of visible-normal sampling of the specular lobe
// (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)) and cosine sampling of the
// diffuse lobe. pdf = pSpec * G1(wo) D(h) / (4 wo.z) + (1 - pSpec) * cos(theta_i) / pi, exact for any wi.
#include "lib/ggx.glsl"
#include "lib/warps.glsl"

// Probability of sampling the specular lobe: 1 for pure metals, else its Fresnel-at-normal share, kept in
// [0.25, 0.9] so that neither lobe is starved.
float ggxSpecularProbability() {
  vec3 f0 = mix(vec3(0.04), color, metallic);
  float specular = dot(f0, vec3(1.0 / 3.0));
  float diffuse = (1.0 - metallic) * dot(color, vec3(1.0 / 3.0));
  if (diffuse <= 0.0) return 1.0;
  return clamp(specular / (specular + diffuse), 0.25, 0.9);
}

vec3 sampleGgxVisibleNormal(vec3 wo, float alpha, vec2 u) {
  vec3 vh = normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));  // hemisphere configuration
  float lensq = dot(vh.xy, vh.xy);
  vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
  vec3 t2 = cross(vh, t1);
  float r = sqrt(u.x), phi = kTwoPi * u.y;  // point on the projected disk
  float p1 = r * cos(phi), p2 = r * sin(phi);
  float s = 0.5 * (1.0 + vh.z);
  p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
  return normalize(vec3(alpha * nh.x, alpha * nh.y, max(1e-7, nh.z)));  // back to the ellipsoid
}

float ggxVndfPdf(vec3 wi, vec3 wo) {
  if (wo.z <= 0.0) return 0.0;
  vec3 h = wi + wo;
  float len2 = dot(h, h);
  if (len2 <= 0.0) return 0.0;
  h *= inversesqrt(len2);
  if (dot(wo, h) <= 0.0) return 0.0;
  return ggxG1(wo, roughness) * ggxD(h, roughness) / (4.0 * wo.z);
}

float brdfPdf(vec3 wi, vec3 wo) {
  float pSpec = ggxSpecularProbability();
  float pdf = pSpec * ggxVndfPdf(wi, wo);
  if (pSpec < 1.0) pdf += (1.0 - pSpec) * cosineHemispherePdf(wi.z);
  return pdf;
}

vec3 brdfSample(vec2 u, vec3 wo, out float pdf) {
  pdf = 0.0;
  if (wo.z <= 0.0) return vec3(0.0, 0.0, 1.0);
  float pSpec = ggxSpecularProbability();
  // The lobe is chosen by u.x < pSpec and u.x is rescaled, so the point set stays 2D. Both warps are computed
  // and one kept: straight-line code for SIMD hardware, where a divergent branch costs both sides anyway.
  bool specular = u.x < pSpec;
  vec2 uSpec = vec2(clamp(u.x / pSpec, 0.0, kOneMinusEpsilon), u.y);  // pSpec >= 0.25
  vec2 uDiffuse = vec2(pSpec < 1.0 ? clamp((u.x - pSpec) / (1.0 - pSpec), 0.0, kOneMinusEpsilon) : 0.0, u.y);
  vec3 wiSpecular = reflect(-wo, sampleGgxVisibleNormal(wo, roughness, uSpec));
  vec3 wiDiffuse = squareToCosineHemisphere(uDiffuse);
  vec3 wi = specular ? wiSpecular : wiDiffuse;
  pdf = brdfPdf(wi, wo);
  return wi;
}
