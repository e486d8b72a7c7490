// Env technique "env-hier": hierarchical 2x2 mip-pyramid warp (engine/sampling/env/env_hier.cpp builds it,
// packEnvHierForGpu lays it out; EnvHierGpuData documents the layout). Every node covers a rectangle of u,
// split where its children's masses put it; the descent compares u with the stored splits, so a texel is
// chosen exactly when u lies in its rectangle, and its probability is that rectangle's area. Low distortion,
// but discontinuous at every quadtree split. pdf = area / the texel's exact solid angle; inside a texel the
// direction is uniform in solid angle. A guide over u starts each descent at the deepest node its cell shares.
#include "lib/latlong.glsl"
#include "lib/table.glsl"

// Interior nodes in heap order: node g's (splitX, splitY of the left column, splitY of the right column, 0)
// in u; its children are 4g + 1 + cx + 2cy; nodes from ENV_HIER_LEAF_START on are texels, in Morton order.
IBLX_TABLE(hierSplits, 4);
// Per cell of a G x G grid over u: the heap index of the deepest node whose rectangle contains the cell.
IBLX_TABLE(hierGuide, 1);
// Per texel, row-major: its rectangle in u (minX, minY, sizeX, sizeY).
IBLX_TABLE(hierTexelRects, 4);

// The even bits of m, compacted (one axis of a Morton index).
uint hierMortonAxis(uint m) {
  m &= 0x55555555u;
  m = (m | (m >> 1u)) & 0x33333333u;
  m = (m | (m >> 2u)) & 0x0f0f0f0fu;
  m = (m | (m >> 4u)) & 0x00ff00ffu;
  return (m | (m >> 8u)) & 0x0000ffffu;
}

vec4 hierTexelRect(ivec2 texel) {
  return tableVec4(hierTexelRects, uint(texel.y * ENV_HIER_WIDTH + texel.x));
}

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  const uint guideSize = ENV_HIER_GUIDE_SIZE;  // a power of two: u * G is exact
  uvec2 cell = min(uvec2(u * float(guideSize)), uvec2(guideSize - 1u));
  uint g = tableUint(hierGuide, cell.y * guideSize + cell.x);
  while (g < ENV_HIER_LEAF_START) {
    vec4 split = tableVec4(hierSplits, g);
    uint cx = u.x >= split.x ? 1u : 0u;  // column first, in the CPU twin's order
    uint cy = u.y >= (cx == 0u ? split.y : split.z) ? 1u : 0u;
    g = 4u * g + 1u + cx + 2u * cy;
  }
  uint m = g - ENV_HIER_LEAF_START;
  // Padding texels have empty rectangles and are never chosen.
  ivec2 texel = min(ivec2(hierMortonAxis(m), hierMortonAxis(m >> 1u)), envSize() - 1);
  vec4 rect = hierTexelRect(texel);  // the chosen texel's size is > 0
  vec2 t = clamp((u - rect.xy) / rect.zw, vec2(0.0), vec2(kOneMinusEpsilon));
  float solidAngle = texelSolidAngle(texel);
  pdf = solidAngle > 0.0 ? rect.z * rect.w / solidAngle : 0.0;
  radiance = envTexelRadiance(texel);
  return texelToDirection(texel, t);
}

float envPdf(vec3 wi, vec3 n) {
  ivec2 texel = directionToTexel(wi);
  vec4 rect = hierTexelRect(texel);
  float solidAngle = texelSolidAngle(texel);
  return solidAngle > 0.0 ? rect.z * rect.w / solidAngle : 0.0;
}
