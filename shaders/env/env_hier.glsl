// Env technique "env-hier": hierarchical 2x2 mip-pyramid warp (engine/sampling/env_hier.cpp builds it,
// packEnvHierForGpu lays it out). Each level splits u by a local ratio of child sums, so float precision holds at
// any dynamic range; low distortion, but discontinuous at every quadtree split. pdf = product of the shares
// actually chosen divided by the texel's exact solid angle; inside a texel the direction is uniform in solid angle.
#include "lib/latlong.glsl"

// Per node of every level but the finest: its children (q00, q10, q01, q11), 0 where missing.
layout(std430, set = 2, binding = 0) readonly buffer EnvHierChildren { vec4 hierChildren[]; };
// Per level, root first: x = offset into hierChildren, y = width, z = height,
// w = splitX | splitY << 1 | shiftX << 8 | shiftY << 16 (doublings from the children down to the finest level).
// A constant from the builder (it depends on the map's size only), so every level's fields are immediates.
const uvec4 hierLevels[ENV_HIER_LEVELS] = ENV_HIER_LEVEL_TABLE;

// Splits between a first child of weight a and a second of weight b: returns 1 for the second, remaps u, and
// multiplies prob by the share taken. A missing second child (b = 0) gives share 1 and leaves u unchanged.
uint hierChoose(float a, float b, inout float u, inout float prob) {
  float total = a + b;
  float pFirst = total > 0.0 ? a / total : 0.5;
  bool second = u >= pFirst;
  float share = second ? 1.0 - pFirst : pFirst;
  float remapped = (second ? u - pFirst : u) / share;  // share > 0: a share of 0 is never chosen
  u = share > 0.0 ? clamp(remapped, 0.0, kOneMinusEpsilon) : 0.0;
  prob *= share;
  return second ? 1u : 0u;
}

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  const uint levelCount = ENV_HIER_LEVELS;  // fixed by the builder: the descent unrolls
  uint x = 0u, y = 0u;
  float prob = 1.0;
  for (uint l = 0u; l < levelCount; ++l) {
    uvec4 level = hierLevels[l];
    vec4 q = hierChildren[level.x + y * level.y + x];
    uint cx = hierChoose(q.x + q.z, q.y + q.w, u.x, prob);  // column first, in the CPU twin's order
    uint cy = hierChoose(cx == 0u ? q.x : q.y, cx == 0u ? q.z : q.w, u.y, prob);
    x = (level.w & 1u) != 0u ? 2u * x + cx : x;
    y = (level.w & 2u) != 0u ? 2u * y + cy : y;
  }
  ivec2 texel = min(ivec2(x, y), envSize() - 1);  // padding texels have weight 0 and are never chosen
  float solidAngle = texelSolidAngle(texel);
  pdf = solidAngle > 0.0 ? prob / solidAngle : 0.0;
  radiance = envTexelRadiance(texel);
  return texelToDirection(texel, u);
}

float envPdf(vec3 wi, vec3 n) {
  uvec2 texel = uvec2(directionToTexel(wi));
  const uint levelCount = ENV_HIER_LEVELS;
  float prob = 1.0;
  // Walk from the root along the path to the texel, multiplying the shares the descent would take.
  for (uint l = 0u; l < levelCount; ++l) {
    uvec4 level = hierLevels[l];
    uint shiftX = (level.w >> 8u) & 0xffu, shiftY = level.w >> 16u;
    bool splitX = (level.w & 1u) != 0u, splitY = (level.w & 2u) != 0u;
    uint x = texel.x >> shiftX, y = texel.y >> shiftY;  // this level's node on the path
    uint cx = splitX ? (texel.x >> (shiftX - 1u)) & 1u : 0u;
    uint cy = splitY ? (texel.y >> (shiftY - 1u)) & 1u : 0u;
    vec4 q = hierChildren[level.x + y * level.y + x];
    float left = q.x + q.z, right = q.y + q.w, total = left + right;
    float pLeft = total > 0.0 ? left / total : 0.5;
    prob *= cx == 0u ? pLeft : 1.0 - pLeft;
    float top = cx == 0u ? q.x : q.y, bottom = cx == 0u ? q.z : q.w, column = top + bottom;
    float pTop = column > 0.0 ? top / column : 0.5;
    prob *= cy == 0u ? pTop : 1.0 - pTop;
  }
  float solidAngle = texelSolidAngle(ivec2(texel));
  return solidAngle > 0.0 ? prob / solidAngle : 0.0;
}
