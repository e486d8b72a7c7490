// Env technique "env-hier": hierarchical 2x2 mip-pyramid warp (engine/sampling/env_hier.cpp builds it,
// packEnvHierForGpu lays it out). Each level splits u by a local ratio of child sums, so float precision holds
// at any dynamic range; low distortion, but discontinuous at every quadtree split. pdf = the texel's
// probability (the product of the shares on its path, tabulated) divided by its exact solid angle; inside a
// texel the direction is uniform in solid angle. A guide over u starts each descent at the deepest node its
// u values share.
#include "lib/latlong.glsl"
#include "lib/table.glsl"

// Interior nodes in heap order (EnvHierGpuData in engine/sampling/env_hier.h): node g's split (pLeft, pTop of
// the left column, pTop of the right column, 0); its children are 4g + 1 + cx + 2cy; nodes from
// ENV_HIER_LEAF_START on are texels, in Morton order.
IBLX_TABLE(2, 0, hierShares);  // 4-word elements
// Per cell of a G x G grid over u: the rectangle of the deepest node containing the whole cell (xy = its lower
// corner in u, zw = 1 / its size), and that node's heap index; the descent starts there.
IBLX_TABLE(2, 1, hierGuideRects);  // 4-word elements
IBLX_TABLE(2, 2, hierGuideNodes);
// Per texel, row-major: its probability, the float product of the shares on its path.
IBLX_TABLE(2, 3, hierTexelProbability);

// Takes the first child when u < pFirst: returns 1 for the second and remaps u into the child taken. The share
// taken is never 0 (u in [0, 1), pFirst in [0, 1]) and the remapped u never negative.
uint hierChoose(float pFirst, inout float u) {
  bool second = u >= pFirst;
  float share = second ? 1.0 - pFirst : pFirst;
  u = min((second ? u - pFirst : u) / share, kOneMinusEpsilon);
  return second ? 1u : 0u;
}

// The even bits of m, compacted (one axis of a Morton index).
uint hierMortonAxis(uint m) {
  m &= 0x55555555u;
  m = (m | (m >> 1u)) & 0x33333333u;
  m = (m | (m >> 2u)) & 0x0f0f0f0fu;
  m = (m | (m >> 4u)) & 0x00ff00ffu;
  return (m | (m >> 8u)) & 0x0000ffffu;
}

float hierTexelProb(ivec2 texel) {
  return tableFloat(hierTexelProbability, uint(texel.y * ENV_HIER_WIDTH + texel.x));
}

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  const uint guideSize = ENV_HIER_GUIDE_SIZE;  // a power of two: u * G is exact
  uvec2 cell = min(uvec2(u * float(guideSize)), uvec2(guideSize - 1u));
  uint entry = cell.y * guideSize + cell.x;
  vec4 startRect = tableVec4(hierGuideRects, entry);
  uint g = tableUint(hierGuideNodes, entry);
  u = clamp((u - startRect.xy) * startRect.zw, vec2(0.0), vec2(kOneMinusEpsilon));
  while (g < ENV_HIER_LEAF_START) {
    vec4 shares = tableVec4(hierShares, g);
    uint cx = hierChoose(shares.x, u.x);  // column first, in the CPU twin's order
    uint cy = hierChoose(cx == 0u ? shares.y : shares.z, u.y);
    g = 4u * g + 1u + cx + 2u * cy;
  }
  uint m = g - ENV_HIER_LEAF_START;
  // Padding texels have probability 0 and are never chosen.
  ivec2 texel = min(ivec2(hierMortonAxis(m), hierMortonAxis(m >> 1u)), envSize() - 1);
  float solidAngle = texelSolidAngle(texel);
  pdf = solidAngle > 0.0 ? hierTexelProb(texel) / solidAngle : 0.0;
  radiance = envTexelRadiance(texel);
  return texelToDirection(texel, u);
}

float envPdf(vec3 wi, vec3 n) {
  ivec2 texel = directionToTexel(wi);
  float solidAngle = texelSolidAngle(texel);
  return solidAngle > 0.0 ? hierTexelProb(texel) / solidAngle : 0.0;
}
