// The CPU rasterizer that turns a triangle mesh into a G-buffer: one shading point per pixel centre (no
// antialiasing, like the analytic sphere), the nearest triangle along the orthographic ray.
#pragma once

#include "engine/geometry/camera.h"
#include "engine/geometry/gbuffer.h"
#include "engine/geometry/mesh.h"

namespace iblx {

// Where the interpolated normal of a pixel faces away from the viewer (n . wo <= 0, possible near
// silhouettes, where it differs from the flat triangle's), it is bent within the plane of n and wo to n . wo
// = this value: the least change that makes the pixel see the environment (every BRDF is 0 for wo below the
// horizon, so the pixel would be black for any material and lighting).
inline constexpr double kBentNormalViewCosine = 0.01;

// Rasterizes `mesh` seen by `camera` into a width x height G-buffer.
// - Coverage: pixel centre (pixelToImagePlane / zoom, as for the sphere) inside a triangle's projection,
// edges
//   included; edge functions are evaluated with the edge's endpoints in a canonical order, so two triangles
//   that share an edge classify every pixel centre consistently and no pixel falls through the seam.
// - Depth: the nearest hit along -back wins (ties: the first triangle in the mesh).
// - Normal: the barycentric interpolation of the vertex normals, normalized. Two-sided: a triangle's front is
//   the side its vertex normals point to (so clockwise files with outward normals work too); seen from
//   behind, the negated normals are used. Then the bend above, if needed.
// - Tangent: tangentFromNormal; view: the camera's back axis (orthographic).
GBuffer rasterizeMesh(const TriMesh& mesh, const CameraSpec& camera, int width, int height);

}  // namespace iblx
