// Env technique "uniform": directions uniform on the sphere (baseline; ignores the map and the normal).
#include "lib/latlong.glsl"
#include "lib/warps.glsl"

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  pdf = kUniformSpherePdf;
  vec3 w = squareToUniformSphere(u);
  radiance = envRadiance(w);
  return w;
}

float envPdf(vec3 wi, vec3 n) { return kUniformSpherePdf; }
