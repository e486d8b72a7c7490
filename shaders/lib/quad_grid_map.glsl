// GPU twin of QuadGridMap (engine/ot/map.h): a map of the unit square given by the images of an
// (OT_GRID+1)^2 vertex grid, one piece per cell (bilinear on strictly convex quads, two affine triangles through
// the reflex corner otherwise), with point location in the image by a quadtree. The env-ot techniques' data
// (engine/sampling/env/env_ot_maps.cpp) fills these buffers: vertices, pieces, quadtree nodes, leaf cell lists.
#ifndef IBLX_LIB_QUAD_GRID_MAP
#define IBLX_LIB_QUAD_GRID_MAP
#include "lib/table.glsl"
#include "lib/constants.glsl"
#include "lib/latlong.glsl"

IBLX_TABLE(quadMapVertex, 2);
IBLX_TABLE(quadMapPiece, 1);
IBLX_TABLE(quadMapNode, 2);  // (first, count)
IBLX_TABLE(quadMapLeafCell, 1);

const uint kQuadPieceBilinear = 0u, kQuadPieceSplitMain = 1u, kQuadPieceSplitAnti = 2u;
const uint kQuadTreeInteriorNode = 0xffffffffu;

float quadCross(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

// The corners of cell `cell` of a vertex grid (this map's, or env-ot-inv's forward map), counter-clockwise.
void quadGridCorners(usamplerBuffer vertices, uint cell, out vec2 c[4]) {
  const uint m = OT_GRID;
  uint i = cell % m, j = cell / m, v = j * (m + 1u) + i;
  c[0] = tableVec2(vertices, v);
  c[1] = tableVec2(vertices, v + 1u);
  c[2] = tableVec2(vertices, v + m + 2u);
  c[3] = tableVec2(vertices, v + m + 1u);
}

void quadMapCorners(uint cell, out vec2 c[4]) { quadGridCorners(quadMapVertex, cell, c); }

// Local (s, t) -> image point; jac = the local Jacobian determinant (per unit s, t).
vec2 quadPieceEvaluate(uint piece, vec2 c[4], vec2 st, out float jac) {
  float s = st.x, t = st.y;
  if (piece == kQuadPieceSplitMain) {
    if (s >= t) {
      jac = quadCross(c[1] - c[0], c[2] - c[1]);
      return c[0] + s * (c[1] - c[0]) + t * (c[2] - c[1]);
    }
    jac = quadCross(c[2] - c[3], c[3] - c[0]);
    return c[0] + s * (c[2] - c[3]) + t * (c[3] - c[0]);
  }
  if (piece == kQuadPieceSplitAnti) {
    if (s + t <= 1.0) {
      jac = quadCross(c[1] - c[0], c[3] - c[0]);
      return c[0] + s * (c[1] - c[0]) + t * (c[3] - c[0]);
    }
    jac = quadCross(c[2] - c[3], c[2] - c[1]);
    return c[2] + (1.0 - s) * (c[3] - c[2]) + (1.0 - t) * (c[1] - c[2]);
  }
  vec2 ds = (1.0 - t) * (c[1] - c[0]) + t * (c[2] - c[3]);
  vec2 dt = (1.0 - s) * (c[3] - c[0]) + s * (c[2] - c[1]);
  jac = quadCross(ds, dt);
  return mix(mix(c[0], c[1], s), mix(c[3], c[2], s), t);
}

bool quadInUnit(vec2 q, float tol) {
  return all(greaterThanEqual(q, vec2(-tol))) && all(lessThanEqual(q, vec2(1.0 + tol)));
}

// (s, t) of y in the triangle o + s a + t b (false when degenerate).
bool quadSolveAffine(vec2 o, vec2 a, vec2 b, vec2 y, out vec2 q) {
  float det = quadCross(a, b);
  vec2 h = y - o;
  q = det > 0.0 ? vec2(quadCross(h, b), quadCross(a, h)) / det : vec2(-1.0);
  return det > 0.0;
}

// Inverse of quadPieceEvaluate; false when y lies outside the piece by more than tol (local units).
bool quadPieceInvert(uint piece, vec2 c[4], vec2 y, float tol, out vec2 st) {
  vec2 q;
  st = vec2(0.0);
  if (piece == kQuadPieceSplitMain) {
    if (quadSolveAffine(c[0], c[1] - c[0], c[2] - c[1], y, q) && quadInUnit(q, tol) && q.x - q.y >= -tol) {
      st = clamp(q, 0.0, 1.0);
      return true;
    }
    if (quadSolveAffine(c[0], c[2] - c[3], c[3] - c[0], y, q) && quadInUnit(q, tol) && q.y - q.x >= -tol) {
      st = clamp(q, 0.0, 1.0);
      return true;
    }
    return false;
  }
  if (piece == kQuadPieceSplitAnti) {
    if (quadSolveAffine(c[0], c[1] - c[0], c[3] - c[0], y, q) && quadInUnit(q, tol) && q.x + q.y <= 1.0 + tol) {
      st = clamp(q, 0.0, 1.0);
      return true;
    }
    if (quadSolveAffine(c[2], c[3] - c[2], c[1] - c[2], y, q)) {
      q = 1.0 - q;
      if (quadInUnit(q, tol) && q.x + q.y >= 1.0 - tol) {
        st = clamp(q, 0.0, 1.0);
        return true;
      }
    }
    return false;
  }
  if (piece != kQuadPieceBilinear) return false;
  // Bilinear: k2 t^2 + k1 t + k0 = 0 (Quilez 2010), cancellation-free roots, then one Newton polish.
  vec2 e = c[1] - c[0], f = c[3] - c[0], g = c[0] - c[1] + c[2] - c[3], h = y - c[0];
  float k2 = quadCross(g, f), k1 = quadCross(e, f) + quadCross(h, g), k0 = quadCross(h, e);
  float roots[2];
  int count = 0;
  float scale = abs(k2) + abs(k1) + abs(k0);
  if (abs(k2) <= 1e-6 * scale) {
    if (k1 != 0.0) roots[count++] = -k0 / k1;
  } else {
    float disc = k1 * k1 - 4.0 * k0 * k2;
    if (disc < 0.0) return false;
    float qq = -0.5 * (k1 + (k1 >= 0.0 ? sqrt(disc) : -sqrt(disc)));
    roots[count++] = qq / k2;
    if (qq != 0.0) roots[count++] = k0 / qq;
  }
  for (int r = 0; r < count; ++r) {
    float t = roots[r];
    vec2 den = e + g * t;
    float s = abs(den.x) >= abs(den.y) ? (h.x - f.x * t) / den.x : (h.y - f.y * t) / den.y;
    q = vec2(s, t);
    if (isnan(s) || isinf(s) || !quadInUnit(q, tol)) continue;
    float jac;
    vec2 r0 = quadPieceEvaluate(kQuadPieceBilinear, c, q, jac) - y;
    vec2 ds = (1.0 - q.y) * (c[1] - c[0]) + q.y * (c[2] - c[3]);
    vec2 dt = (1.0 - q.x) * (c[3] - c[0]) + q.x * (c[2] - c[1]);
    if (jac > 0.0) q -= vec2(quadCross(r0, dt), quadCross(ds, r0)) / jac;
    if (!quadInUnit(q, tol)) continue;
    st = clamp(q, 0.0, 1.0);
    return true;
  }
  return false;
}

// Domain point x in [0,1]^2 -> image point; jac = det of the map's Jacobian (domain units).
// quadMapApply for the grid map given by `vertices` and `pieces`.
vec2 quadGridApply(usamplerBuffer vertices, usamplerBuffer pieces, vec2 x, out float jac) {
  const uint m = OT_GRID;
  vec2 scaled = clamp(x, 0.0, 1.0) * float(m);
  uvec2 ij = min(uvec2(scaled), uvec2(m - 1u));
  uint cell = ij.y * m + ij.x;
  vec2 c[4];
  quadGridCorners(vertices, cell, c);
  vec2 p = quadPieceEvaluate(tableUint(pieces, cell), c, clamp(scaled - vec2(ij), 0.0, 1.0), jac);
  jac *= float(m) * float(m);
  return p;
}

vec2 quadMapApply(vec2 x, out float jac) { return quadGridApply(quadMapVertex, quadMapPiece, x, jac); }

// Image point y -> domain point x inside cell `cell`'s piece (jac as for quadMapApply at x); false when y lies
// outside the piece by more than tol (local units).
bool quadMapInvertCell(uint cell, vec2 y, float tol, out vec2 x, out float jac) {
  const uint m = OT_GRID;
  vec2 c[4];
  quadMapCorners(cell, c);
  uint piece = tableUint(quadMapPiece, cell);
  vec2 st;
  x = vec2(0.0);
  jac = 0.0;
  if (!quadPieceInvert(piece, c, y, tol, st)) return false;
  quadPieceEvaluate(piece, c, st, jac);
  jac *= float(m) * float(m);
  x = (vec2(cell % m, cell / m) + st) / float(m);
  return true;
}

// Image point y -> domain point x (jac as for quadMapApply at x). The quadtree descent has at most the
// builder's depth (OT_TREE_DEPTH) steps and a leaf lists at most OT_LARGEST_LEAF cells, so the cost is
// bounded by construction; false when no piece contains y (a rounding gap, or an Invalid piece).
bool quadMapInvert(vec2 y, out vec2 x, out float jac) {
  uint node = 0u;
  vec2 lo = vec2(0.0), hi = vec2(1.0);
  for (uint d = 0u; d <= OT_TREE_DEPTH && tableUvec2(quadMapNode, node).y == kQuadTreeInteriorNode; ++d) {
    vec2 mid = 0.5 * (lo + hi);
    uint q = (y.x >= mid.x ? 1u : 0u) + (y.y >= mid.y ? 2u : 0u);
    if ((q & 1u) != 0u) lo.x = mid.x; else hi.x = mid.x;
    if ((q & 2u) != 0u) lo.y = mid.y; else hi.y = mid.y;
    node = tableUvec2(quadMapNode, node).x + q;
  }
  uvec2 leaf = tableUvec2(quadMapNode, node);
  x = vec2(0.0);
  jac = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    float tol = pass == 0 ? 1e-5 : 1e-3;
    for (uint k = 0u; k < leaf.y; ++k)
      if (quadMapInvertCell(tableUint(quadMapLeafCell, leaf.x + k), y, tol, x, jac)) return true;
  }
  return false;
}

// The OT maps' density square: column u = phi / 2pi as in docs/DESIGN.md §3, and row r of OT_DENSITY_GRID covering
// theta in [pi r / N, pi (r+1) / N] as in the lat-long map, but with cos(theta) (not theta) linear inside the
// row. Each cell keeps its mass (otDensityFromEnv integrates over the same cells), while the solid angle per
// unit parameter area becomes constant within a row: the pdf stays bounded at the poles instead of growing
// like 1 / sin(theta). Returns the direction; jacobian = dOmega / (du dv) in that row.
vec3 otParameterToDirection(vec2 x, out float jacobian) {
  const float n = float(OT_DENSITY_GRID);
  float r = min(floor(x.y * n), n - 1.0), f = clamp(x.y * n - r, 0.0, 1.0);
  float theta0 = kPi * r / n, theta1 = kPi * (r + 1.0) / n;
  float rowDelta = 2.0 * sin(0.5 * (theta0 + theta1)) * sin(0.5 * (theta1 - theta0));  // cos0 - cos1
  jacobian = kTwoPi * n * rowDelta;
  // 1 - cos(theta) and 1 + cos(theta) each from the nearer pole's side, so neither cancels.
  float s0 = sin(0.5 * theta0), c1 = cos(0.5 * theta1);
  float oneMinusCos = 2.0 * s0 * s0 + f * rowDelta, onePlusCos = 2.0 * c1 * c1 + (1.0 - f) * rowDelta;
  float cosTheta = x.y < 0.5 ? 1.0 - oneMinusCos : onePlusCos - 1.0;
  float sinTheta = sqrt(max(oneMinusCos * onePlusCos, 0.0));
  float phi = kTwoPi * x.x;
  return vec3(sinTheta * cos(phi), cosTheta, sinTheta * sin(phi));
}

// Inverse of otParameterToDirection.
vec2 otDirectionToParameter(vec3 w, out float jacobian) {
  const float n = float(OT_DENSITY_GRID);
  vec2 latLong = directionToLatLong(w);  // (phi / 2pi, theta / pi)
  float theta = kPi * latLong.y;
  float r = min(floor(latLong.y * n), n - 1.0);
  float theta0 = kPi * r / n, theta1 = kPi * (r + 1.0) / n;
  float rowDelta = 2.0 * sin(0.5 * (theta0 + theta1)) * sin(0.5 * (theta1 - theta0));
  jacobian = kTwoPi * n * rowDelta;
  float f = 2.0 * sin(0.5 * (theta + theta0)) * sin(0.5 * (theta - theta0)) / rowDelta;  // (cos0 - cos) / delta
  return vec2(latLong.x, (r + clamp(f, 0.0, 1.0)) / n);
}
#endif
