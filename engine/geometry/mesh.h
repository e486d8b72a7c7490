// Triangle meshes for the CPU rasterizer: positions with one shading normal each, smooth normals computed
// from the faces, fitting into the unit sphere, and the built-in plane.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace iblx {

struct TriMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;  // one per position, unit length; the side the surface faces
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from the normals' side
};

// Twice the area of triangle t times its unit normal (right-handed winding): (p1 - p0) x (p2 - p0).
glm::dvec3 triangleAreaNormal(const TriMesh& mesh, const std::array<std::uint32_t, 3>& t);

// Area-weighted smooth normals: each vertex gets the normalized sum of (p1 - p0) x (p2 - p0) over the
// triangles that use it, i.e. facet normals weighted by twice the triangle's area (Gouraud 1971 averages
// facet normals; Max 1999, "Weights for Computing Vertex Normals from Facet Normals", JGT 4(2), compares
// weightings). A vertex whose sum cancels takes the normal of its largest triangle; one used by no triangle
// of non-zero area gets +Z.
void computeSmoothNormals(TriMesh& mesh);

// Drops triangles of zero area (including those that repeat a vertex); returns how many were dropped.
std::size_t dropDegenerateTriangles(TriMesh& mesh);

// Moves the bounding-box centre to the origin and scales uniformly so the farthest vertex is at distance 1:
// the default camera then frames the mesh. Returns the scale applied. The mesh must have a non-zero extent.
double fitToUnitSphere(TriMesh& mesh);

// The built-in plane: the square [-1,1]^2 of the xy-plane at z = 0, two triangles with normal +Z.
TriMesh makePlaneMesh();

}  // namespace iblx
