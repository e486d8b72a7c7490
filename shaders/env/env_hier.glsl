// Env technique "env-hier": hierarchical 2x2 mip-pyramid warp (engine/sampling/env_hier.cpp builds it,
// packEnvHierForGpu lays it out). Each level splits u by a local ratio of child sums, so float precision holds
// at any dynamic range; low distortion, but discontinuous at every quadtree split. pdf = product of the shares
// actually chosen divided by the texel's exact solid angle; inside a texel the direction is uniform in solid
// angle. A guide over u starts each descent at the deepest node its u values share.
#include "lib/latlong.glsl"
#include "lib/table.glsl"

// Interior nodes in heap order (EnvHierGpuData in engine/sampling/env_hier.h): node g's split (pLeft, pTop of
// the left column, pTop of the right column, 0), 1 along an axis that does not split. Node g's children are
// 2g + 1 + c below ENV_HIER_ONE_AXIS_NODES (levels that split the longer axis only) and
// 4g + ENV_HIER_QUAD_CHILD_OFFSET + cx + 2cy after; nodes from ENV_HIER_LEAF_START on are texels.
IBLX_TABLE(2, 0, hierShares);  // 4-word elements
// Per cell of a G x G grid over u: the deepest node containing the whole cell, where the descent starts.
// Two elements per cell: rect (xy = the node's lower corner in u, zw = 1 / its size), then node (heap
// index, x, y, the bits of its probability).
IBLX_TABLE(2, 1, hierGuide);  // 4-word elements

uint hierChild(uint g, uint cx, uint cy) {
  return g < ENV_HIER_ONE_AXIS_NODES ? 2u * g + 1u + cx + cy
                                     : uint(int(4u * g) + ENV_HIER_QUAD_CHILD_OFFSET) + cx + 2u * cy;
}

// Takes the first child with probability pFirst: returns 1 for the second, remaps u, and multiplies prob by
// the share taken. pFirst = 1 (no split along this axis) leaves u unchanged.
uint hierChoose(float pFirst, inout float u, inout float prob) {
  bool second = u >= pFirst;
  float share = second ? 1.0 - pFirst : pFirst;
  float remapped = (second ? u - pFirst : u) / share;  // share > 0: a share of 0 is never chosen
  u = share > 0.0 ? clamp(remapped, 0.0, kOneMinusEpsilon) : 0.0;
  prob *= share;
  return second ? 1u : 0u;
}

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  const uint guideSize = ENV_HIER_GUIDE_SIZE;  // a power of two: u * G is exact
  uvec2 cell = min(uvec2(u * float(guideSize)), uvec2(guideSize - 1u));
  uint entry = 2u * (cell.y * guideSize + cell.x);
  vec4 startRect = tableVec4(hierGuide, entry);
  uvec4 startNode = tableUvec4(hierGuide, entry + 1u);
  u = clamp((u - startRect.xy) * startRect.zw, vec2(0.0), vec2(kOneMinusEpsilon));
  uint g = startNode.x, x = startNode.y, y = startNode.z;
  float prob = uintBitsToFloat(startNode.w);
  while (g < ENV_HIER_LEAF_START) {
    vec4 shares = tableVec4(hierShares, g);
    uint cx = hierChoose(shares.x, u.x, prob);  // column first, in the CPU twin's order
    uint cy = hierChoose(cx == 0u ? shares.y : shares.z, u.y, prob);
    x = 2u * x + cx;  // along an axis that does not split, c = 0 and the coordinate stays 0
    y = 2u * y + cy;
    g = hierChild(g, cx, cy);
  }
  ivec2 texel = min(ivec2(x, y), envSize() - 1);  // padding texels have weight 0 and are never chosen
  float solidAngle = texelSolidAngle(texel);
  pdf = solidAngle > 0.0 ? prob / solidAngle : 0.0;
  radiance = envTexelRadiance(texel);
  return texelToDirection(texel, u);
}

float envPdf(vec3 wi, vec3 n) {
  uvec2 texel = uvec2(directionToTexel(wi));
  const uint interiorLevels = ENV_HIER_LEVELS - 1u;  // fixed by the builder: the walk unrolls
  uint g = 0u;
  float prob = 1.0;
  // Walk from the root along the path to the texel, multiplying the shares the descent would take. Level l+1
  // is 2^(bits - (L - l - 1)) wide when that exponent is positive, else 1 wide (no split along that axis).
  for (uint l = 0u; l < interiorLevels; ++l) {
    uint shift = interiorLevels - 1u - l;  // doublings from level l+1 down to the finest
    uint cx = l + 1u + ENV_HIER_BITS_X > interiorLevels ? (texel.x >> shift) & 1u : 0u;
    uint cy = l + 1u + ENV_HIER_BITS_Y > interiorLevels ? (texel.y >> shift) & 1u : 0u;
    vec4 shares = tableVec4(hierShares, g);
    prob *= cx == 0u ? shares.x : 1.0 - shares.x;
    float pTop = cx == 0u ? shares.y : shares.z;
    prob *= cy == 0u ? pTop : 1.0 - pTop;
    g = hierChild(g, cx, cy);
  }
  float solidAngle = texelSolidAngle(ivec2(texel));
  return solidAngle > 0.0 ? prob / solidAngle : 0.0;
}
