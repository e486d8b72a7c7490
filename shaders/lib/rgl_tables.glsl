// The table of an RGL-EPFL material (engine/sampling/brdf/rgl_sampling.h, RglBsdf::techniqueData) and the
// bilinear warps read from it: the GLSL twin of engine/sampling/bilinear_warp.cpp (the continuous inversion
// of Dupuy & Jakob 2018's reader), shared by shaders/brdf/rgl.glsl and shaders/brdf_technique/rgl_vndf.glsl.
// Sizes and offsets into rglData come from the RGL_* defines.
#ifndef IBLX_LIB_RGL_TABLES
#define IBLX_LIB_RGL_TABLES
#extension GL_EXT_control_flow_attributes : require
#include "lib/table.glsl"
#include "lib/constants.glsl"

IBLX_TABLE(rglData, 1);

float rglAt(uint i) { return tableFloat(rglData, i); }

// Every loop here has a trip count known at compile time (the RGL_*_STEPS defines are ceil(log2(n - 1)) of
// their grids) and is unrolled: on lavapipe an invocation may run only about 65535 loop iterations in all,
// beyond which loops end early, and the reference kernel evaluates the BRDF many times per invocation.

// The largest i in [0, n - 2] with rglData[base + i] < value, for increasing entries; 0 when none is. A
// branch-free binary search of `steps` halvings.
uint rglFindInterval(uint base, uint n, uint steps, float value) {
  uint lo = 0u, len = n - 1u;
  [[unroll]] for (uint step = 0u; step < steps; ++step) {
    uint halfLen = len >> 1u;
    lo = rglAt(base + lo + halfLen) < value ? lo + halfLen : lo;
    len -= halfLen;
  }
  return lo;
}

// The up to four (phi_i, theta_i) slices around the view and their weights; slice = iPhi * nTheta + iTheta.
struct RglCorners {
  uvec4 slice;
  vec4 weight;
};

// The slices as one parameter: node i and i + 1 (clamped) with the upper one's weight.
void rglParam(uint at, uint n, uint steps, float value, out uint i0, out uint i1, out float w1) {
  if (n < 2u) {
    i0 = 0u, i1 = 0u, w1 = 0.0;
    return;
  }
  i0 = rglFindInterval(at, n, steps, value);
  i1 = i0 + 1u;
  w1 = clamp((value - rglAt(at + i0)) / (rglAt(at + i1) - rglAt(at + i0)), 0.0, 1.0);
}

RglCorners rglCorners(float phi, float theta) {
  uint p0, p1, t0, t1;
  float wp, wt;
  rglParam(RGL_AT_PHI, RGL_N_PHI, RGL_PHI_STEPS, phi, p0, p1, wp);
  rglParam(RGL_AT_THETA, RGL_N_THETA, RGL_THETA_STEPS, theta, t0, t1, wt);
  RglCorners c;
  c.slice = uvec4(p0 * RGL_N_THETA + t0, p0 * RGL_N_THETA + t1, p1 * RGL_N_THETA + t0, p1 * RGL_N_THETA + t1);
  c.weight = vec4((1.0 - wp) * (1.0 - wt), (1.0 - wp) * wt, wp * (1.0 - wt), wp * wt);
  return c;
}

// One slice of weight 1: the tables that do not depend on the view (ndf, sigma).
RglCorners rglSingleSlice() {
  RglCorners c;
  c.slice = uvec4(0u);
  c.weight = vec4(1.0, 0.0, 0.0, 0.0);
  return c;
}

// table[at + slice * sliceSize + index] blended over the corners; slices are scaled by `sliceScale` and
// offset by `sliceOffset` (the rgb table's channel slices).
float rglLookup(uint at, uint index, uint sliceSize, RglCorners c, uint sliceScale, uint sliceOffset) {
  float v = 0.0;
  [[unroll]] for (int k = 0; k < 4; ++k)
    if (c.weight[k] > 0.0) v += c.weight[k] * rglAt(at + (c.slice[k] * sliceScale + sliceOffset) * sliceSize + index);
  return v;
}

// The bilinear interpolant at pos in [0, 1]^2 (a grid of w x h values).
float rglInterpolate(uint at, uint w, uint h, vec2 pos, RglCorners c, uint sliceScale, uint sliceOffset) {
  pos = clamp(pos, 0.0, 1.0) * vec2(float(w - 1u), float(h - 1u));
  uvec2 cell = min(uvec2(pos), uvec2(w - 2u, h - 2u));
  vec2 t = pos - vec2(cell);
  uint i = cell.y * w + cell.x, size = w * h;
  float v00 = rglLookup(at, i, size, c, sliceScale, sliceOffset);
  float v10 = rglLookup(at, i + 1u, size, c, sliceScale, sliceOffset);
  float v01 = rglLookup(at, i + w, size, c, sliceScale, sliceOffset);
  float v11 = rglLookup(at, i + w + 1u, size, c, sliceScale, sliceOffset);
  return mix(mix(v00, v10, t.x), mix(v01, v11, t.x), t.y);
}

// t in [0, 1] with integral_0^t ((1 - s) a + s b) ds = y: the root of the quadratic in the form without
// cancellation, 2 y / (a + sqrt(a^2 - 2 y (a - b))), which also covers a = b.
float rglInvertLinear(float y, float a, float b) {
  float d = a + sqrt(max(a * a - 2.0 * y * (a - b), 0.0));
  return d > 0.0 ? clamp(2.0 * y / d, 0.0, 1.0) : 0.0;
}

// A warp of w x h normalized values at `at`, conditional CDFs at `cond` and marginal CDFs at `marg`; its
// searches take colSteps and rowSteps halvings.
struct RglWarp {
  uint at, cond, marg, w, h, colSteps, rowSteps;
};

// Uniform u to a point of the warp: (x, y) and its density on [0, 1]^2 in z.
vec3 rglWarpSample(RglWarp warp, vec2 u, RglCorners c) {
  uint w = warp.w, size = warp.w * warp.h;
  u = clamp(u, 1e-7, kOneMinusEpsilon);
  // Row: the largest row whose marginal CDF lies below u.y (a blend of the slices' CDFs).
  uint row = 0u, len = warp.h - 1u;
  [[unroll]] for (uint step = 0u; step < warp.rowSteps; ++step) {
    uint halfLen = len >> 1u;
    row = rglLookup(warp.marg, row + halfLen, warp.h, c, 1u, 0u) < u.y ? row + halfLen : row;
    len -= halfLen;
  }
  float r0 = rglLookup(warp.cond, row * w + w - 1u, size, c, 1u, 0u);
  float r1 = rglLookup(warp.cond, (row + 1u) * w + w - 1u, size, c, 1u, 0u);
  float ty = rglInvertLinear(u.y - rglLookup(warp.marg, row, warp.h, c, 1u, 0u), r0, r1);
  // Column, in the row interpolated at ty.
  float target = u.x * mix(r0, r1, ty);
  uint col = 0u;
  len = w - 1u;
  [[unroll]] for (uint step = 0u; step < warp.colSteps; ++step) {
    uint halfLen = len >> 1u, mid = col + halfLen;
    float cdf = mix(rglLookup(warp.cond, row * w + mid, size, c, 1u, 0u),
                    rglLookup(warp.cond, (row + 1u) * w + mid, size, c, 1u, 0u), ty);
    col = cdf < target ? mid : col;
    len -= halfLen;
  }
  uint i = row * w + col;
  float below = mix(rglLookup(warp.cond, i, size, c, 1u, 0u), rglLookup(warp.cond, i + w, size, c, 1u, 0u), ty);
  float v00 = rglLookup(warp.at, i, size, c, 1u, 0u), v10 = rglLookup(warp.at, i + 1u, size, c, 1u, 0u);
  float v01 = rglLookup(warp.at, i + w, size, c, 1u, 0u), v11 = rglLookup(warp.at, i + w + 1u, size, c, 1u, 0u);
  float c0 = mix(v00, v01, ty), c1 = mix(v10, v11, ty);
  float tx = rglInvertLinear(target - below, c0, c1);
  vec2 cells = vec2(float(w - 1u), float(warp.h - 1u));
  return vec3((vec2(col, row) + vec2(tx, ty)) / cells, mix(c0, c1, tx) * cells.x * cells.y);
}

// The inverse: the uniform point that rglWarpSample maps to pos, and the density at pos in z.
vec3 rglWarpInvert(RglWarp warp, vec2 pos, RglCorners c) {
  uint w = warp.w, size = warp.w * warp.h;
  vec2 cells = vec2(float(w - 1u), float(warp.h - 1u));
  pos = clamp(pos, 0.0, 1.0) * cells;
  uvec2 cell = min(uvec2(pos), uvec2(w - 2u, warp.h - 2u));
  vec2 t = pos - vec2(cell);
  uint i = cell.y * w + cell.x;
  float v00 = rglLookup(warp.at, i, size, c, 1u, 0u), v10 = rglLookup(warp.at, i + 1u, size, c, 1u, 0u);
  float v01 = rglLookup(warp.at, i + w, size, c, 1u, 0u), v11 = rglLookup(warp.at, i + w + 1u, size, c, 1u, 0u);
  float c0 = mix(v00, v01, t.y), c1 = mix(v10, v11, t.y);
  float r0 = rglLookup(warp.cond, cell.y * w + w - 1u, size, c, 1u, 0u);
  float r1 = rglLookup(warp.cond, (cell.y + 1u) * w + w - 1u, size, c, 1u, 0u);
  float rowIntegral = mix(r0, r1, t.y);
  float x = t.x * (c0 + 0.5 * t.x * (c1 - c0)) +
            mix(rglLookup(warp.cond, i, size, c, 1u, 0u), rglLookup(warp.cond, i + w, size, c, 1u, 0u), t.y);
  float y = t.y * (r0 + 0.5 * t.y * (r1 - r0)) + rglLookup(warp.marg, cell.y, warp.h, c, 1u, 0u);
  return vec3(rowIntegral > 0.0 ? x / rowIntegral : 0.0, y, mix(c0, c1, t.x) * cells.x * cells.y);
}

const RglWarp kRglVndf = RglWarp(RGL_AT_VNDF, RGL_AT_VNDF_COND, RGL_AT_VNDF_MARG, RGL_VNDF_W, RGL_VNDF_H,
                                 RGL_VNDF_W_STEPS, RGL_VNDF_H_STEPS);
const RglWarp kRglLuminance =
    RglWarp(RGL_AT_LUM, RGL_AT_LUM_COND, RGL_AT_LUM_MARG, RGL_N, RGL_N, RGL_N_STEPS, RGL_N_STEPS);

// Spherical coordinates and the unit square of the tables (theta = u^2 pi / 2, phi = (2u - 1) pi).
float rglElevation(vec3 w) { return 2.0 * asin(clamp(0.5 * length(vec3(w.xy, w.z - 1.0)), 0.0, 1.0)); }
float rglThetaToU(float theta) { return sqrt(max(theta, 0.0) * (2.0 / kPi)); }
float rglPhiToU(float phi) { return (phi + kPi) / (2.0 * kPi); }

// The signs that mirror the view into a reduced file's stored azimuths (1 for a full turn); applied again
// they undo it.
vec2 rglReduction(vec3 view) {
  if (RGL_REDUCTION < 2) return vec2(1.0);
  float sy = view.y < 0.0 ? 1.0 : -1.0;
  float sx = RGL_REDUCTION == 4 ? (view.x < 0.0 ? 1.0 : -1.0) : sy;
  return vec2(sx, sy);
}

// u of the microfacet normal m seen from the view at azimuth phiV (relative azimuth for isotropic files).
vec2 rglNormalToU(vec3 m, float phiV) {
  float phiM = atan(m.y, m.x);
  vec2 u = vec2(rglThetaToU(rglElevation(m)), rglPhiToU(RGL_ISOTROPIC != 0 ? phiM - phiV : phiM));
  u.y -= floor(u.y);
  return u;
}

// Solid angle per unit square of (u_theta, u_phi): 2 pi^2 u_theta sin(theta).
float rglUnitSquareJacobian(float uTheta, float theta) { return 2.0 * kPi * kPi * uTheta * sin(theta); }
#endif
