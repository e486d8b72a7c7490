// Env technique "env-ot-inv": the tabulated inverse of the optimal-transport map (ot_map.h tabulatedInverse: the
// forward map inverted on the vertices of a regular grid over the uniform square). A sample is one bilinear
// (or affine) lookup, x = G(u); its density in the density square is 1 / |det DG(u)| of the piece evaluated,
// divided by dOmega / dx of otParameterToDirection for solid angle. The pdf of an arbitrary direction (MIS)
// needs its preimage: the quadtree over G's image locates it and the piece is inverted.
#include "lib/latlong.glsl"
#include "lib/quad_grid_map.glsl"

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  float jac, solidAngle;
  vec2 x = quadMapApply(u, jac);
  vec3 w = otParameterToDirection(x, solidAngle);
  pdf = (jac > 0.0 && solidAngle > 0.0) ? 1.0 / (jac * solidAngle) : 0.0;
  radiance = pdf > 0.0 ? envRadiance(w) : vec3(0.0);
  return w;
}

float envPdf(vec3 wi, vec3 n) {
  vec2 u;
  float jac, solidAngle;
  if (!quadMapInvert(otDirectionToParameter(wi, solidAngle), u, jac)) return 0.0;
  return (jac > 0.0 && solidAngle > 0.0) ? 1.0 / (jac * solidAngle) : 0.0;
}
