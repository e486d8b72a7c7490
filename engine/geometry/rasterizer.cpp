// The CPU mesh rasterizer (engine/geometry/rasterizer.h): a bounding-box scan converter with a depth buffer,
// then one shading pass over the visible hits.
#include "engine/geometry/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace iblx {
namespace {

// Twice the signed area of (a, b, q): > 0 when q is to the left of a -> b.
double orient(glm::dvec2 a, glm::dvec2 b, glm::dvec2 q) {
  return (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
}

// orient() with the endpoints in lexicographic order, negated when swapped: exactly antisymmetric in (p0,
// p1), so the two triangles on either side of an edge agree on which side every pixel centre is.
double edge(glm::dvec2 p0, glm::dvec2 p1, glm::dvec2 q) {
  if (p1.x < p0.x || (p1.x == p0.x && p1.y < p0.y)) return -orient(p1, p0, q);
  return orient(p0, p1, q);
}

constexpr std::uint32_t kNoHit = std::numeric_limits<std::uint32_t>::max();

}  // namespace

GBuffer rasterizeMesh(const TriMesh& mesh, const CameraSpec& camera, int width, int height) {
  checkCamera(camera);
  const CameraFrame frame = cameraFrame(camera);
  GBuffer g = makeBackgroundGBuffer(frame, width, height);

  // Pixel centres on the image plane in world units (camera x, y), as for the sphere; x depends on i only.
  std::vector<double> xs(static_cast<std::size_t>(width)), ys(static_cast<std::size_t>(height));
  for (int i = 0; i < width; ++i)
    xs[std::size_t(i)] = frame.onPlane(pixelToImagePlane(i, 0, width, height)).x;
  for (int j = 0; j < height; ++j)
    ys[std::size_t(j)] = frame.onPlane(pixelToImagePlane(0, j, width, height)).y;
  // Inverse of pixelToImagePlane / zoom, for the pixel range of a bounding box.
  const double aspect = double(width) / double(height);
  auto columnOf = [&](double x) { return (x * camera.zoom / aspect + 1.0) * 0.5 * width - 0.5; };
  auto rowOf = [&](double y) { return (1.0 - y * camera.zoom) * 0.5 * height - 0.5; };

  std::vector<glm::dvec3> cam(mesh.positions.size());  // x right, y up, z towards the viewer
  for (std::size_t v = 0; v < cam.size(); ++v) cam[v] = frame.toCamera(mesh.positions[v]);

  const std::size_t pixelCount = std::size_t(width) * std::size_t(height);
  std::vector<double> depth(pixelCount, -std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> hit(pixelCount, kNoHit);
  std::vector<glm::dvec2> barycentric(pixelCount);  // (b1, b2); b0 = 1 - b1 - b2

  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const glm::dvec3 &a = cam[tri[0]], &b = cam[tri[1]], &c = cam[tri[2]];
    const glm::dvec2 pa(a), pb(b), pc(c);  // on the image plane
    const double area = orient(pa, pb, pc);
    if (area == 0.0) continue;  // seen edge-on: covers no pixel centre
    // Pixel range of the bounding box, a pixel wider on each side; the edge test below decides.
    const double i0 = std::max(0.0, std::floor(columnOf(std::min({a.x, b.x, c.x})))),
                 i1 = std::min(double(width - 1), std::ceil(columnOf(std::max({a.x, b.x, c.x})))),
                 j0 = std::max(0.0, std::floor(rowOf(std::max({a.y, b.y, c.y})))),
                 j1 = std::min(double(height - 1), std::ceil(rowOf(std::min({a.y, b.y, c.y}))));
    if (!(i0 <= i1 && j0 <= j1)) continue;
    for (int j = int(j0); j <= int(j1); ++j)
      for (int i = int(i0); i <= int(i1); ++i) {
        const glm::dvec2 q(xs[std::size_t(i)], ys[std::size_t(j)]);
        const double w0 = edge(pb, pc, q), w1 = edge(pc, pa, q), w2 = edge(pa, pb, q);
        const bool inside =
            area > 0.0 ? (w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0) : (w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0);
        const double sum = w0 + w1 + w2;
        if (!inside || sum == 0.0) continue;
        const double b1 = w1 / sum, b2 = w2 / sum;
        // Orthographic: depth is affine on the image plane, so it interpolates with the barycentrics.
        const double z = a.z + b1 * (b.z - a.z) + b2 * (c.z - a.z);
        const std::size_t p = std::size_t(j) * std::size_t(width) + std::size_t(i);
        if (z > depth[p]) {
          depth[p] = z;
          hit[p] = std::uint32_t(t);
          barycentric[p] = {b1, b2};
        }
      }
  }

  for (std::size_t p = 0; p < pixelCount; ++p) {
    if (hit[p] == kNoHit) continue;
    const auto& tri = mesh.triangles[hit[p]];
    const glm::dvec3 &n0 = mesh.normals[tri[0]], &n1 = mesh.normals[tri[1]], &n2 = mesh.normals[tri[2]];
    // The triangle's front is the side of its vertex normals, whatever the winding.
    glm::dvec3 ng = triangleAreaNormal(mesh, tri);
    if (glm::dot(ng, n0 + n1 + n2) < 0.0) ng = -ng;
    const double b1 = barycentric[p].x, b2 = barycentric[p].y;
    glm::dvec3 n = (1.0 - b1 - b2) * n0 + b1 * n1 + b2 * n2;
    if (glm::dot(ng, frame.back) < 0.0) {  // seen from behind: two-sided
      n = -n;
      ng = -ng;
    }
    const double length = glm::length(n);
    n = length > 1e-12 ? n / length : glm::normalize(ng);
    if (const double cosView = glm::dot(n, frame.back); cosView <= 0.0) {
      // Bend within the plane of n and wo to n . wo = kBentNormalViewCosine (rasterizer.h).
      const glm::dvec3 tangential = n - cosView * frame.back;
      const double tangentialLength = glm::length(tangential);
      n = tangentialLength > 1e-12 ? std::sqrt(1.0 - kBentNormalViewCosine * kBentNormalViewCosine) *
                                             (tangential / tangentialLength) +
                                         kBentNormalViewCosine * frame.back
                                   : frame.back;
    }
    setObjectPixel(g.pixels[p], n, frame.back);
  }
  return g;
}

}  // namespace iblx
