// Mesh helpers (engine/geometry/mesh.h).
#include "engine/geometry/mesh.h"

#include "engine/core/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace iblx {

glm::dvec3 triangleAreaNormal(const TriMesh& mesh, const std::array<std::uint32_t, 3>& t) {
  const glm::dvec3 &p0 = mesh.positions[t[0]], &p1 = mesh.positions[t[1]], &p2 = mesh.positions[t[2]];
  return glm::cross(p1 - p0, p2 - p0);
}

void computeSmoothNormals(TriMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0)), largest(n, glm::dvec3(0.0));
  for (const auto& t : mesh.triangles) {
    const glm::dvec3 areaNormal = triangleAreaNormal(mesh, t);
    for (const std::uint32_t v : t) {
      sum[v] += areaNormal;
      if (glm::dot(areaNormal, areaNormal) > glm::dot(largest[v], largest[v])) largest[v] = areaNormal;
    }
  }
  mesh.normals.assign(n, glm::dvec3(0.0, 0.0, 1.0));
  for (std::size_t v = 0; v < n; ++v) {
    // Relative threshold: the sum cancels when its length is rounding noise against the largest face.
    const double scale = glm::length(largest[v]);
    if (scale == 0.0) continue;
    mesh.normals[v] = glm::length(sum[v]) > 1e-9 * scale ? glm::normalize(sum[v]) : largest[v] / scale;
  }
}

std::size_t dropDegenerateTriangles(TriMesh& mesh) {
  const std::size_t before = mesh.triangles.size();
  std::erase_if(mesh.triangles, [&](const std::array<std::uint32_t, 3>& t) {
    const glm::dvec3 a = triangleAreaNormal(mesh, t);
    return !(glm::dot(a, a) > 0.0);
  });
  return before - mesh.triangles.size();
}

double fitToUnitSphere(TriMesh& mesh) {
  IBLX_ASSERT(!mesh.positions.empty());
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const auto& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  double radius = 0.0;
  for (const auto& p : mesh.positions) radius = std::max(radius, glm::length(p - centre));
  IBLX_ASSERT(radius > 0.0);
  const double scale = 1.0 / radius;
  for (auto& p : mesh.positions) p = (p - centre) * scale;
  return scale;
}

TriMesh makePlaneMesh() {
  TriMesh mesh;
  mesh.positions = {{-1.0, -1.0, 0.0}, {1.0, -1.0, 0.0}, {1.0, 1.0, 0.0}, {-1.0, 1.0, 0.0}};
  mesh.normals.assign(4, glm::dvec3(0.0, 0.0, 1.0));
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

}  // namespace iblx
