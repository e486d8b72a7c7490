// env-ot's inverse (direction -> u), one preimage per branch: the map's rows and the split sun's row
// (engine/sampling/product/env_ot_product.h, whose envOtPreimages is the CPU twin). Needs the env technique env-ot
// (shaders/env_technique/env_ot.glsl, its tables) and envOtProductTechniqueData's tables and ENV_OT_GRID.
#ifndef IBLX_LIB_ENV_OT_INVERSE
#define IBLX_LIB_ENV_OT_INVERSE
#include "lib/table.glsl"
#include "lib/latlong.glsl"

IBLX_TABLE(envOtTexelEntryFirst, 1);  // W*H + 1: texel t's entries [first[t], first[t + 1])
IBLX_TABLE(envOtTexelEntry, 2);       // (piece, row): the map's pieces, then the sun row's (row ENV_OT_GRID)
IBLX_TABLE(envOtBranchPdf, 2);        // per texel: (q_map, q_sun) w.r.t. solid angle

vec2 envOtBranchPdfs(ivec2 texel) {
  return tableVec2(envOtBranchPdf, uint(texel.y) * frame.envWidth + uint(texel.x));
}

// u of the point `local` (the rescaled (u.x, u.y) the piece was placed with) of entry (piece, row).
vec2 envOtEntryToU(uvec2 entry, vec2 local) {
  uint at = entry.x + entry.y;
  float c0 = tableFloat(envOtPieceCdf, at), c1 = tableFloat(envOtPieceCdf, at + 1u);
  float r0 = tableFloat(envOtRowCdf, entry.y), r1 = tableFloat(envOtRowCdf, entry.y + 1u);
  return vec2(c0 + local.x * (c1 - c0), r0 + local.y * (r1 - r0));
}

// The preimages of wi in its texel: through the map's piece that holds it (a whole texel, else the first
// triangle that holds it, else, on an edge within rounding, the triangle whose smallest barycentric
// coordinate is the largest) and through the sun row; a flag per branch says whether it reaches the texel.
void envOtPreimages(vec3 wi, ivec2 texel, out vec2 uMap, out bool hasMap, out vec2 uSun, out bool hasSun) {
  uint index = uint(texel.y) * frame.envWidth + uint(texel.x);
  uint first = tableUint(envOtTexelEntryFirst, index), end = tableUint(envOtTexelEntryFirst, index + 1u);
  vec2 t = directionToTexelOffset(wi, texel);
  hasMap = false;
  hasSun = false;
  uMap = vec2(0.0);
  uSun = vec2(0.0);
  float bestInside = -3.0e38;
  uvec2 best = uvec2(0u);
  vec2 bestLocal = vec2(0.0);
  if (end > first) {
    uvec2 last = tableUvec2(envOtTexelEntry, end - 1u);
    if (last.y >= ENV_OT_GRID) {  // the sun row's whole texel, the last entry
      uSun = envOtEntryToU(last, t);
      hasSun = true;
      --end;
    }
  }
  for (uint e = first; e < end && bestInside < 0.0; ++e) {
    uvec2 entry = tableUvec2(envOtTexelEntry, e);
    uvec4 piece = tableUvec4(envOtPiece, entry.x);
    if ((piece.x & kEnvOtTriangle) == 0u) {
      best = entry;
      bestLocal = t;
      hasMap = true;
      break;
    }
    vec2 a = unpackUnorm2x16(piece.y), b = unpackUnorm2x16(piece.z), c = unpackUnorm2x16(piece.w);
    float det = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (det == 0.0) continue;
    float beta = ((t.x - a.x) * (c.y - a.y) - (t.y - a.y) * (c.x - a.x)) / det;
    float gamma = ((b.x - a.x) * (t.y - a.y) - (b.y - a.y) * (t.x - a.x)) / det;
    float inside = min(min(1.0 - beta - gamma, beta), gamma);
    if (inside > bestInside) {
      // The inverse of Osada et al.'s map: sqrt(r1) = beta + gamma, r2 = gamma / sqrt(r1).
      float root = clamp(beta + gamma, 0.0, 1.0);
      bestLocal = vec2(root * root, root > 0.0 ? clamp(gamma / root, 0.0, 1.0) : 0.0);
      bestInside = inside;
      best = entry;
      hasMap = true;
    }
  }
  if (hasMap) uMap = envOtEntryToU(best, bestLocal);
}
#endif
