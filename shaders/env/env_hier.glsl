// Env technique "env-hier": hierarchical 2x2 mip-pyramid warp (built by engine/sampling/env_hier.cpp).
// Each level splits u by a local ratio of child sums, so float precision holds at any dynamic range; low
// distortion, but discontinuous at every quadtree split. pdf = product of the shares actually chosen divided by
// the texel's exact solid angle; inside a texel the direction is uniform in solid angle.
#include "lib/latlong.glsl"

layout(std430, set = 2, binding = 0) readonly buffer EnvHierNodes { float hierNodes[]; };
// Per level, coarsest (1x1) first: x = offset into hierNodes, y = width, z = height.
layout(std430, set = 2, binding = 1) readonly buffer EnvHierLevels { uvec4 hierLevels[]; };

float hierNode(uvec4 level, uint x, uint y) { return hierNodes[level.x + y * level.y + x]; }

// Chooses between two children with weights a (first) and b; remaps u; returns the share taken.
float hierSplit(float a, float b, inout float u, out uint second) {
  float total = a + b;
  float pFirst = total > 0.0 ? a / total : 0.5;
  if (u < pFirst) {
    second = 0u;
    u = clamp(u / pFirst, 0.0, kOneMinusEpsilon);
    return pFirst;
  }
  second = 1u;
  float pSecond = 1.0 - pFirst;
  u = pSecond > 0.0 ? clamp((u - pFirst) / pSecond, 0.0, kOneMinusEpsilon) : 0.0;
  return pSecond;
}

// Share of child (cx, cy) in the step from `coarse` node (x, y) to `fine`, as the descent computes it.
float hierStepShare(uvec4 fine, uint x, uint y, uint cx, uint cy, bool twoX, bool twoY) {
  uint x0 = twoX ? 2u * x : x, y0 = twoY ? 2u * y : y;
  float q00 = hierNode(fine, x0, y0);
  float q10 = twoX ? hierNode(fine, x0 + 1u, y0) : 0.0;
  float q01 = twoY ? hierNode(fine, x0, y0 + 1u) : 0.0;
  float q11 = (twoX && twoY) ? hierNode(fine, x0 + 1u, y0 + 1u) : 0.0;
  float share = 1.0;
  if (twoX) {
    float total = (q00 + q01) + (q10 + q11);  // the order envSample adds them in
    float pLeft = total > 0.0 ? (q00 + q01) / total : 0.5;
    share *= cx == 0u ? pLeft : 1.0 - pLeft;
  }
  if (twoY) {
    float top = cx == 0u ? q00 : q10, bottom = cx == 0u ? q01 : q11;
    float total = top + bottom;
    float pTop = total > 0.0 ? top / total : 0.5;
    share *= cy == 0u ? pTop : 1.0 - pTop;
  }
  return share;
}

vec3 envSample(vec2 u, vec3 n, out float pdf) {
  uint levelCount = uint(hierLevels.length());
  uint x = 0u, y = 0u;
  float prob = 1.0;
  for (uint l = 1u; l < levelCount; ++l) {
    uvec4 coarse = hierLevels[l - 1u], fine = hierLevels[l];
    bool twoX = fine.y > coarse.y, twoY = fine.z > coarse.z;
    uint x0 = twoX ? 2u * x : x, y0 = twoY ? 2u * y : y;
    float q00 = hierNode(fine, x0, y0);
    float q10 = twoX ? hierNode(fine, x0 + 1u, y0) : 0.0;
    float q01 = twoY ? hierNode(fine, x0, y0 + 1u) : 0.0;
    float q11 = (twoX && twoY) ? hierNode(fine, x0 + 1u, y0 + 1u) : 0.0;
    uint cx = 0u, cy = 0u;
    if (twoX) prob *= hierSplit(q00 + q01, q10 + q11, u.x, cx);
    if (twoY) prob *= cx == 0u ? hierSplit(q00, q01, u.y, cy) : hierSplit(q10, q11, u.y, cy);
    x = x0 + cx;
    y = y0 + cy;
  }
  ivec2 texel = min(ivec2(x, y), envSize() - 1);  // padding texels have weight 0 and are never chosen
  float solidAngle = texelSolidAngle(texel);
  pdf = solidAngle > 0.0 ? prob / solidAngle : 0.0;
  return texelToDirection(texel, u);
}

float envPdf(vec3 wi, vec3 n) {
  ivec2 texel = directionToTexel(wi);
  uint levelCount = uint(hierLevels.length());
  uvec4 finest = hierLevels[levelCount - 1u];
  float prob = 1.0;
  // Walk down from the root along the path that leads to the texel, multiplying the same shares.
  for (uint l = 1u; l < levelCount; ++l) {
    uvec4 coarse = hierLevels[l - 1u], fine = hierLevels[l];
    bool twoX = fine.y > coarse.y, twoY = fine.z > coarse.z;
    // Level sizes are powers of two, so the number of doublings below level l is a difference of exponents.
    uint shiftX = uint(findMSB(finest.y) - findMSB(fine.y)), shiftY = uint(findMSB(finest.z) - findMSB(fine.z));
    uint fx = uint(texel.x) >> shiftX, fy = uint(texel.y) >> shiftY;  // node at level l on the path
    uint x = twoX ? fx >> 1u : fx, y = twoY ? fy >> 1u : fy;
    prob *= hierStepShare(fine, x, y, twoX ? (fx & 1u) : 0u, twoY ? (fy & 1u) : 0u, twoX, twoY);
  }
  float solidAngle = texelSolidAngle(texel);
  return solidAngle > 0.0 ? prob / solidAngle : 0.0;
}
