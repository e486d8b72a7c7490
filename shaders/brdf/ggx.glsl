// BRDF "ggx": a metallic-roughness material, f = diffuse + D G2 F / (4 cos_i cos_o), F = Schlick with
// F0 = mix(0.04, color, metallic). The diffuse lobe (1 - metallic) color / pi is weighted by
// (1 - F_d(cos_i)) (1 - F_d(cos_o)), F_d the dielectric Schlick term, which keeps it reciprocal and leaves the
// energy the specular lobe takes at grazing angles (without it the albedo exceeds 1 near grazing views).
// Parameters: color, roughness (the GGX alpha), metallic.
#include "lib/ggx.glsl"

vec3 brdfEval(vec3 wi, vec3 wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
  vec3 h = normalize(wi + wo);
  vec3 f0 = mix(vec3(0.04), color, metallic);
  vec3 specular = fresnelSchlick(f0, dot(wi, h)) * (ggxD(h, roughness) * ggxG2(wi, wo, roughness) /
                                                   (4.0 * wi.z * wo.z));
  if (metallic >= 1.0) return specular;  // a uniform branch: no diffuse lobe to evaluate
  float diffuseWeight = (1.0 - fresnelSchlick(vec3(0.04), wi.z).x) * (1.0 - fresnelSchlick(vec3(0.04), wo.z).x);
  return (1.0 - metallic) * diffuseWeight * color * kInvPi + specular;
}
