// Env technique "cosine": cosine-weighted hemisphere around the shading normal (ignores the map).
#include "lib/latlong.glsl"
#include "lib/warps.glsl"

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  vec3 t, b;
  orthonormalBasis(n, t, b);
  vec3 local = squareToCosineHemisphere(u);
  pdf = cosineHemispherePdf(local.z);
  vec3 w = normalize(local.x * t + local.y * b + local.z * n);
  radiance = envRadiance(w);
  return w;
}

float envPdf(vec3 wi, vec3 n) { return cosineHemispherePdf(dot(wi, n)); }
