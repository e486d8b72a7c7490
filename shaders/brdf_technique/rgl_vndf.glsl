// BRDF technique "rgl-vndf": an RGL-EPFL material's own warps (Dupuy & Jakob 2018, §6). u goes through the
// luminance warp, the result through the VNDF warp to a microfacet normal, and the light is the view
// reflected about it; the density is the product of the two warps' densities over the Jacobian of the
// reflection and of the unit-square parametrization. GPU twin of RglBsdf::sample and RglBsdf::pdf
// (engine/sampling/brdf/rgl_sampling.cpp).
#include "lib/rgl_tables.glsl"

vec3 brdfSample(vec2 u, vec3 wo, out float pdf) {
  pdf = 0.0;
  if (wo.z <= 0.0) return vec3(0.0, 0.0, 1.0);
  vec2 s = rglReduction(wo);
  vec3 view = vec3(s * wo.xy, wo.z);
  float thetaV = rglElevation(view), phiV = atan(view.y, view.x);
  RglCorners c = rglCorners(phiV, thetaV);
  vec3 lum = rglWarpSample(kRglLuminance, u, c);
  vec3 normal = rglWarpSample(kRglVndf, lum.xy, c);
  float thetaM = normal.x * normal.x * (0.5 * kPi);
  float phiM = (2.0 * normal.y - 1.0) * kPi + (RGL_ISOTROPIC != 0 ? phiV : 0.0);
  vec3 m = vec3(sin(thetaM) * cos(phiM), sin(thetaM) * sin(phiM), cos(thetaM));
  float cosVM = dot(view, m);
  float jacobian = rglUnitSquareJacobian(normal.x, thetaM) * 4.0 * cosVM;
  float density = normal.z * lum.z / jacobian;
  if (!(jacobian > 0.0) || !(density > 0.0) || isinf(density)) return vec3(0.0, 0.0, 1.0);
  vec3 light = 2.0 * cosVM * m - view;
  pdf = density;
  return normalize(vec3(s * light.xy, light.z));
}

float brdfPdf(vec3 wi, vec3 wo) {
  if (wo.z <= 0.0) return 0.0;
  vec2 s = rglReduction(wo);
  vec3 view = vec3(s * wo.xy, wo.z), light = vec3(s * wi.xy, wi.z);
  vec3 h = view + light;
  if (dot(h, h) <= 0.0) return 0.0;
  vec3 m = normalize(h);
  if (m.z <= 0.0) return 0.0;
  float thetaV = rglElevation(view), phiV = atan(view.y, view.x);
  vec2 uM = rglNormalToU(m, phiV);
  RglCorners c = rglCorners(phiV, thetaV);
  vec3 normal = rglWarpInvert(kRglVndf, uM, c);
  float lum = rglInterpolate(RGL_AT_LUM, RGL_N, RGL_N, normal.xy, c, 1u, 0u) * float((RGL_N - 1u) * (RGL_N - 1u));
  float jacobian = rglUnitSquareJacobian(uM.x, rglElevation(m)) * 4.0 * dot(view, m);
  float density = normal.z * lum / jacobian;
  return jacobian > 0.0 && density > 0.0 && !isinf(density) ? density : 0.0;
}
