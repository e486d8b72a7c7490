// Env technique "uniform": directions uniform on the sphere (baseline; ignores the map and the normal).
#include "lib/warps.glsl"

vec3 envSample(vec2 u, vec3 n, out float pdf) {
  pdf = kUniformSpherePdf;
  return squareToUniformSphere(u);
}

float envPdf(vec3 wi, vec3 n) { return kUniformSpherePdf; }
