// Bicubic Bézier patch sets and their tessellation into a welded triangle mesh: how iblx makes the Utah
// teapot (assets/teapot_patches.txt -> `iblx make-teapot` -> assets/teapot.obj).
#pragma once

#include "engine/geometry/mesh.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace iblx {

struct BezierPatchSet {
  std::vector<glm::dvec3> controlPoints;
  // Zero-based control-point indices of each patch's 4x4 grid, row by row: entry 4 r + c is P_rc, with the
  // column c along u and the row r along v.
  std::vector<std::array<std::uint32_t, 16>> patches;
};

// Reads the format of assets/teapot_patches.txt: '#' comments and blank lines, "patches N", N lines of 16
// one-based indices, "vertices M", M lines "x y z". Throws iblx::Error "FILE:LINE: problem".
BezierPatchSet readBezierPatches(const std::filesystem::path& path);

// Newell's z-up coordinates to iblx's +Y up: (x, y, z) -> (x, z, -y), a rotation of -90° about +X.
void zUpToYUp(BezierPatchSet& set);

// A point of a patch with its partial derivatives.
struct PatchPoint {
  glm::dvec3 position, du, dv;
};

// P(u, v) = sum_r sum_c B_c(u) B_r(v) P_rc with the cubic Bernstein polynomials B_k(t) = C(3,k) t^k
// (1-t)^(3-k), and dP/du, dP/dv from B_k' (Farin, "Curves and Surfaces for CAGD", the chapter on
// tensor-product Bézier patches).
PatchPoint evaluateBicubic(const BezierPatchSet& set, std::size_t patch, double u, double v);

// The unit normal of a patch at (u, v): normalize(dP/du x dP/dv). Where that cross product vanishes (a patch
// edge collapsed to a point, as at the pole of the teapot's lid and bottom), the normal is taken 1e-4 inside
// the patch in both parameters: the limit of the normal towards the pole, to O(1e-4).
glm::dvec3 patchNormal(const BezierPatchSet& set, std::size_t patch, double u, double v);

// Evaluates every patch on an (N+1) x (N+1) grid of (u, v) = (i/N, j/N) and splits each grid cell into two
// triangles wound counter-clockwise about the normal. Samples closer than 1e-8 of the control points' extent
// become one vertex (patch seams and collapsed edges are welded), whose normal is the normalized mean of its
// samples' normals, so neighbouring patches share them; triangles that welding made degenerate are dropped.
// Samples whose normals point to opposite sides (a crease sharper than 90°) are not welded: two surfaces that
// only touch keep their own normals.
TriMesh tessellateBezierPatches(const BezierPatchSet& set, int subdivisions);

}  // namespace iblx
