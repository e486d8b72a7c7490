// Reads one G-buffer entry and expresses its frame in the environment frame (rotation about +Y).
#ifndef IBLX_LIB_PIXEL_SHADING
#define IBLX_LIB_PIXEL_SHADING
#include "lib/frame_resources.glsl"
#include "lib/shading.glsl"

vec3 worldToEnv(vec3 w) {
  float c = frame.envRotation.x, s = frame.envRotation.y;
  return vec3(c * w.x + s * w.z, w.y, -s * w.x + c * w.z);
}

Shading pixelShading(GPixel g) {
  Shading s;
  s.n = normalize(worldToEnv(g.normal.xyz));
  s.t = normalize(worldToEnv(g.tangent.xyz));
  s.b = cross(s.n, s.t);
  s.wo = normalize(worldToEnv(g.view.xyz));
  s.woLocal = toLocal(s, s.wo);
  return s;
}
#endif
