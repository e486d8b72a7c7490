// BRDF of an RGL-EPFL .bsdf file (Dupuy & Jakob 2018; engine/io/rgl_bsdf.h): the microfacet normal's point
// in the VNDF warp's unit square is found by inverting the warp, the rgb table is read there, and the
// Jacobian ndf / (4 sigma) is multiplied back (files with jacobian = 1), giving f cos(theta_wi); divided by
// the cosine for iblx's f. The view is the files' "incident" direction. GPU twin of RglBsdf::eval
// (engine/sampling/brdf/rgl_sampling.cpp).
#include "lib/rgl_tables.glsl"

vec3 brdfEval(vec3 wi, vec3 wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return vec3(0.0);
  vec2 s = rglReduction(wo);
  vec3 view = vec3(s * wo.xy, wo.z), light = vec3(s * wi.xy, wi.z);
  vec3 m = normalize(view + light);
  float thetaV = rglElevation(view), phiV = atan(view.y, view.x);
  vec2 uM = rglNormalToU(m, phiV);
  vec2 uV = vec2(rglThetaToU(thetaV), rglPhiToU(phiV));
  RglCorners c = rglCorners(phiV, thetaV);
  vec2 p = rglWarpInvert(kRglVndf, uM, c).xy;
  vec3 value;
  [[unroll]] for (uint k = 0u; k < 3u; ++k)
    value[k] = max(rglInterpolate(RGL_AT_RGB, RGL_N, RGL_N, p, c, 3u, k), 0.0);
#if RGL_JACOBIAN
  RglCorners one = rglSingleSlice();
  float sigma = rglInterpolate(RGL_AT_SIGMA, RGL_SIGMA_W, RGL_SIGMA_H, uV, one, 1u, 0u);
  value *= sigma > 0.0 ? rglInterpolate(RGL_AT_NDF, RGL_NDF_W, RGL_NDF_H, uM, one, 1u, 0u) / (4.0 * sigma) : 0.0;
#endif
  return value / wi.z;
}
