// Env technique "env-ot": the texel-exact optimal-transport sampler (engine/sampling/env/env_ot.h, whose
// EnvOtSampler is the CPU twin). u.y picks a row of the OT grid (or the sun's row), u.x a piece of the row (its
// pieces ordered by cell), each by a guided float CDF whose choice rescales the coordinate; the direction is
// placed in the piece: a whole texel takes the rescaled u as its t, a triangle maps it uniformly (Osada et al.
// 2002, "Shape distributions", eq. 1). Every piece lies in one texel and is uniform in solid angle there, with
// its share of the texel's weight, so the pdf is the texel pdf of env-cdf.
#include "lib/table.glsl"
#include "lib/constants.glsl"
#include "lib/latlong.glsl"

IBLX_TABLE(envOtRowCdf, 1);      // rows + 1
IBLX_TABLE(envOtRowGuide, 1);    // ENV_OT_ROW_GUIDE_SIZE cells, lo | hi << 16 (float_cdf.h writeGuide)
IBLX_TABLE(envOtRow, 4);         // per row: first piece, first guide cell, guide cells; rows + 1 records
IBLX_TABLE(envOtPieceCdf, 1);    // per row j at its first piece + j: the CDF over its pieces
IBLX_TABLE(envOtPieceGuide, 1);  // per row: its guide cells
IBLX_TABLE(envOtPiece, 4);       // per piece: texel | triangle bit 31, then the triangle's corners (unorm16 x2)
IBLX_TABLE(envOtTexelPdf, 1);    // per texel: its pdf w.r.t. solid angle

const uint kEnvOtTriangle = 0x80000000u;

float envOtPdfOfTexel(ivec2 texel) {
  return tableFloat(envOtTexelPdf, uint(texel.y) * frame.envWidth + uint(texel.x));
}

// The bin k of u in the CDF at base (largest k with cdf[k] <= u, so never a zero-width bin), searched in
// [lo, hi] of guide cell u * cells (cells a power of two, so u * cells is exact), and u rescaled to [0, 1)
// inside it.
int envOtBin(usamplerBuffer cdf, uint base, usamplerBuffer guide, uint guideBase, uint cells, inout float u) {
  uint range = tableUint(guide, guideBase + min(uint(u * float(cells)), cells - 1u));
  int lo = int(range & 0xffffu);
  int k = tableSearchFloat(cdf, base, lo, int(range >> 16u) - lo + 1, u);
  float start = tableFloat(cdf, base + uint(k)), width = tableFloat(cdf, base + uint(k) + 1u) - start;
  u = width > 0.0 ? clamp((u - start) / width, 0.0, kOneMinusEpsilon) : 0.5;
  return k;
}

vec3 envSample(vec2 u, vec3 n, out float pdf, out vec3 radiance) {
  int row = envOtBin(envOtRowCdf, 0u, envOtRowGuide, 0u, ENV_OT_ROW_GUIDE_SIZE, u.y);
  uvec4 record = tableUvec4(envOtRow, uint(row));
  uint count = tableUvec4(envOtRow, uint(row) + 1u).x - record.x;
  pdf = 0.0;
  radiance = vec3(0.0);
  if (count == 0u) return vec3(0.0, 1.0, 0.0);  // a row of zero mass is never chosen
  int k = envOtBin(envOtPieceCdf, record.x + uint(row), envOtPieceGuide, record.y, record.z, u.x);
  uvec4 piece = tableUvec4(envOtPiece, record.x + uint(k));
  uint index = piece.x & ~kEnvOtTriangle;
  ivec2 texel = ivec2(index % frame.envWidth, index / frame.envWidth);
  vec2 t = u;
  if ((piece.x & kEnvOtTriangle) != 0u) {
    float root = sqrt(u.x);
    t = (1.0 - root) * unpackUnorm2x16(piece.y) + root * (1.0 - u.y) * unpackUnorm2x16(piece.z) +
        (root * u.y) * unpackUnorm2x16(piece.w);
  }
  pdf = envOtPdfOfTexel(texel);
  radiance = envTexelRadiance(texel);
  return texelToDirection(texel, t);
}

float envPdf(vec3 wi, vec3 n) { return envOtPdfOfTexel(directionToTexel(wi)); }
