// Env technique "env-ot-fwd": the optimal-transport forward map (engine/ot/solver.h, untangled by
// engine/ot/map.h) evaluated on the fly. A sample u of the uniform square is located in the forward quad mesh by the
// quadtree and the cell's piece inverted: x = F^-1(u) in the density square. Its density there is |det DF(x)| of
// the piece actually evaluated, divided by dOmega / dx of otParameterToDirection for solid angle; the pdf of
// any direction is the same determinant at its own parameter point.
// Near-delta texels (suns) are sampled apart (lib/ot_sun.glsl): the map carries the capped density only.
#include "lib/latlong.glsl"
#include "lib/ot_sun.glsl"
#include "lib/quad_grid_map.glsl"

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  vec2 x;
  vec3 w;
  ivec2 texel;
  float jac, solidAngle, pSun;
  pdf = 0.0;
  radiance = vec3(0.0);
  if (otSunChoose(u)) {
    w = otSunSample(u, texel, pSun);
    quadMapApply(otDirectionToParameter(w, solidAngle), jac);
  } else {
    if (!quadMapInvert(u, x, jac)) return vec3(0.0, 1.0, 0.0);
    w = otParameterToDirection(x, solidAngle);
    texel = directionToTexel(w);
    pSun = otSunTexelPdf(texel);
  }
  pdf = otSunMixture(pSun, (jac > 0.0 && solidAngle > 0.0) ? jac / solidAngle : 0.0);
  radiance = envTexelRadiance(texel);
  return w;
}

float envPdf(vec3 wi, vec3 n) {
  float jac, solidAngle;
  quadMapApply(otDirectionToParameter(wi, solidAngle), jac);
  return otSunMixture(otSunTexelPdf(directionToTexel(wi)), (jac > 0.0 && solidAngle > 0.0) ? jac / solidAngle : 0.0);
}
