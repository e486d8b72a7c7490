// Tests of the camera, the analytic sphere's G-buffer under orbit and zoom, and the CPU mesh rasterizer
// (engine/geometry/camera.h, gbuffer.h, rasterizer.h) against analytic expectations.
#include "engine/geometry/camera.h"
#include "engine/geometry/gbuffer.h"
#include "engine/geometry/obj_file.h"
#include "engine/geometry/rasterizer.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

using namespace iblx;
using namespace iblx::test;

namespace {

glm::dvec3 xyz(const gpu::vec4& v) {
  return {v.x, v.y, v.z};
}

// The sphere G-buffer exactly as iblx built it before cameras had an orbit (docs/DESIGN.md §3), kept here verbatim so
// that the default camera can be checked bit for bit against it.
GBuffer designSphereGBuffer(int width, int height) {
  GBuffer g{width, height, std::vector<gpu::GPixel>(std::size_t(width) * height)};
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      auto& px = g.pixels[std::size_t(j) * width + i];
      const CameraRay ray = pixelToImagePlane(i, j, width, height);
      if (auto n = sphereNormalAt(ray)) {
        const glm::dvec3 t = glm::normalize(glm::dvec3(n->z, 0.0, -n->x));
        px.normal = {float(n->x), float(n->y), float(n->z), 1.0f};
        px.tangent = {float(t.x), float(t.y), float(t.z), 0.0f};
        px.view = {0.0f, 0.0f, 1.0f, 0.0f};
      } else {
        const glm::dvec3 d = glm::normalize(glm::dvec3(ray.x, ray.y, -1.0));
        px.normal = {0.0f, 0.0f, 1.0f, 0.0f};
        px.tangent = {1.0f, 0.0f, 0.0f, 0.0f};
        px.view = {float(d.x), float(d.y), float(d.z), 0.0f};
      }
    }
  return g;
}

// A UV sphere of radius 1: `rings` bands of latitude, `segments` of longitude, exact normals (= positions) or
// none.
std::string uvSphereObj(int segments, int rings, bool normals) {
  std::string text;
  auto index = [&](int ring, int segment) {
    return std::to_string(ring * segments + segment % segments + 1);
  };
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = kPi * r / rings, phi = 2.0 * kPi * s / segments;
      const glm::dvec3 p(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      char line[128];
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
      text += line;
      if (normals) text += "vn" + std::string(line + 1);
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const std::string a = index(r, s), b = index(r + 1, s), c = index(r + 1, s + 1), d = index(r, s + 1);
      auto corner = [&](const std::string& v) { return normals ? v + "//" + v : v; };
      text += "f " + corner(a) + " " + corner(b) + " " + corner(c) + " " + corner(d) + "\n";
    }
  return text;
}

// Checks the invariants of every G-buffer: unit normal and tangent, orthogonal, view = the camera's back axis
// for object pixels, n . wo > 0.
void checkFrames(const GBuffer& g, const CameraSpec& camera) {
  const glm::dvec3 back = cameraFrame(camera).back;
  int bad = 0;
  for (const auto& px : g.pixels) {
    if (px.normal.w == 0.0f) continue;
    const glm::dvec3 n = xyz(px.normal), t = xyz(px.tangent), v = xyz(px.view);
    bad += std::abs(glm::length(n) - 1.0) > 1e-6 || std::abs(glm::length(t) - 1.0) > 1e-6 ||
           std::abs(glm::dot(n, t)) > 1e-6 || glm::length(v - back) > 1e-6 || !(glm::dot(n, v) > 0.0);
  }
  CHECK(bad == 0);
}

}  // namespace

TEST_CASE("camera: the default frame is docs/DESIGN.md §3's; orbits rotate it about the origin") {
  const CameraFrame f = cameraFrame({});
  CHECK(f.right == glm::dvec3(1, 0, 0));
  CHECK(f.up == glm::dvec3(0, 1, 0));
  CHECK(f.back == glm::dvec3(0, 0, 1));
  // Azimuth 90: on +X looking down -X, right = -Z. Elevation 90: above, looking down -Y.
  const CameraFrame side = cameraFrame({90, 0, 1});
  CHECK(glm::length(side.back - glm::dvec3(1, 0, 0)) < 1e-15);
  CHECK(glm::length(side.right - glm::dvec3(0, 0, -1)) < 1e-15);
  const CameraFrame top = cameraFrame({0, 90, 1});
  CHECK(glm::length(top.back - glm::dvec3(0, 1, 0)) < 1e-15);
  CHECK(glm::length(top.up - glm::dvec3(0, 0, -1)) < 1e-15);
  for (const CameraSpec c : {CameraSpec{37, -20, 2}, CameraSpec{-150, 80, 0.5}, CameraSpec{400, 45, 1}}) {
    const CameraFrame r = cameraFrame(c);
    CHECK(glm::length(glm::cross(r.right, r.up) - r.back) < 1e-12);  // right-handed, orthonormal
    CHECK(std::abs(glm::length(r.right) - 1.0) < 1e-12);
    CHECK(std::abs(glm::dot(r.right, r.up)) < 1e-12);
    // Elevation is the angle of back above the horizon; azimuth its angle from +Z towards +X.
    CHECK(std::asin(r.back.y) * 180.0 / kPi == doctest::Approx(c.elevationDeg));
    CHECK(r.right.y == 0.0);
  }
  // The engine names the setting (engine/core/setting.h); the front ends name the flag or control.
  CHECK(contains(errorMessage([] {
                   checkCamera({0, 91, 1});
                 }),
                 "camera orbit 0,91: the azimuth must be finite"));
  CHECK(contains(errorMessage([] { checkCamera({NAN, 0, 1}); }), "camera orbit nan,0"));
  CHECK(contains(errorMessage([] { checkCamera({0, 0, 0}); }), "zoom 0: must be a finite number > 0"));
  CHECK(contains(errorMessage([] { checkCamera({0, 0, INFINITY}); }), "zoom inf"));
}

TEST_CASE("camera: the tangent field follows latitudes about +Y, with +X at the poles") {
  CHECK(glm::length(tangentFromNormal({0, 0, 1}) - glm::dvec3(1, 0, 0)) < 1e-15);
  CHECK(glm::length(tangentFromNormal({1, 0, 0}) - glm::dvec3(0, 0, -1)) < 1e-15);
  CHECK(glm::length(tangentFromNormal({0, 1, 0}) - glm::dvec3(1, 0, 0)) < 1e-15);
  CHECK(glm::length(tangentFromNormal({0, -1, 0}) - glm::dvec3(1, 0, 0)) < 1e-15);
  std::mt19937 rng(3);
  std::normal_distribution<double> gauss;
  for (int k = 0; k < 1000; ++k) {
    glm::dvec3 n = glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
    if (k % 10 == 0)
      n = glm::normalize(glm::dvec3(1e-8 * gauss(rng), 1.0, 1e-8 * gauss(rng)));  // near a pole
    const glm::dvec3 t = tangentFromNormal(n);
    CHECK(std::abs(glm::length(t) - 1.0) < 1e-12);
    CHECK(std::abs(glm::dot(t, n)) < 1e-9);
  }
}

TEST_CASE("sphere G-buffer: the default camera is bit-identical to docs/DESIGN.md §3's sphere") {
  for (const auto& [w, h] : {std::pair{64, 64}, std::pair{33, 17}, std::pair{16, 40}}) {
    const GBuffer expected = designSphereGBuffer(w, h);
    const GBuffer actual = makeSphereGBuffer(w, h);
    REQUIRE(actual.pixels.size() == expected.pixels.size());
    CHECK(std::memcmp(actual.pixels.data(), expected.pixels.data(),
                      actual.pixels.size() * sizeof(gpu::GPixel)) == 0);
    const GBuffer named = makeGBuffer("sphere", {}, w, h);
    CHECK(std::memcmp(named.pixels.data(), expected.pixels.data(),
                      named.pixels.size() * sizeof(gpu::GPixel)) == 0);
  }
}

TEST_CASE("sphere G-buffer: orbit 90,0 sees the sphere from +X; zoom scales the image plane") {
  const int w = 48, h = 32;
  const GBuffer g = makeSphereGBuffer(w, h, {90, 0, 1});
  int objects = 0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const auto& px = g.pixels[std::size_t(j) * w + i];
      const CameraRay r = pixelToImagePlane(i, j, w, h);
      const double r2 = r.x * r.x + r.y * r.y;
      REQUIRE((px.normal.w == 1.0f) == (r2 < 1.0));
      if (r2 >= 1.0) {
        // Background: the pinhole direction (x, y, -1) in camera space, i.e. (1 on -X, y, x on -Z).
        CHECK(glm::length(xyz(px.view) - glm::normalize(glm::dvec3(-1.0, r.y, -r.x))) < 1e-6);
        continue;
      }
      ++objects;
      // Camera (x, y, z) -> world x right + y up + z back, with right = -Z, back = +X.
      const glm::dvec3 n(std::sqrt(1.0 - r2), r.y, -r.x);
      CHECK(glm::length(xyz(px.normal) - n) < 1e-6);
      CHECK(glm::length(xyz(px.view) - glm::dvec3(1, 0, 0)) < 1e-6);
      CHECK(glm::length(xyz(px.tangent) - tangentFromNormal(n)) < 1e-6);
    }
  CHECK(objects > 500);
  checkFrames(g, {90, 0, 1});

  // Zoom 0.5: the sphere covers the pixels whose image-plane point is within 1/2 of the centre, with the
  // normal of the point at twice that distance.
  const GBuffer small = makeSphereGBuffer(w, h, {0, 0, 0.5});
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const auto& px = small.pixels[std::size_t(j) * w + i];
      const CameraRay r = pixelToImagePlane(i, j, w, h);
      REQUIRE((px.normal.w == 1.0f) == (4.0 * (r.x * r.x + r.y * r.y) < 1.0));
      if (px.normal.w == 1.0f) CHECK(std::abs(px.normal.x - 2.0 * r.x) < 1e-6);
    }
}

TEST_CASE("rasterizer: the plane has normal +Z, tangent +X and its projected coverage at every orbit") {
  const int w = 64, h = 48;  // not square: x spans [-4/3, 4/3]; no pixel centre lies on a coverage boundary
  for (const double elevation : {0.0, 60.0, 70.0, 85.0, -45.0}) {
    CAPTURE(elevation);
    const CameraSpec camera{0, elevation, 1};
    const GBuffer g = makeGBuffer("plane", camera, w, h);
    const double cosElevation = std::cos(elevation * kPi / 180.0);
    int expected = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        // The plane's point (x, y, 0) appears at (x, y cos(elevation)).
        const CameraRay r = pixelToImagePlane(i, j, w, h);
        const bool covered = std::abs(r.x) < 1.0 && std::abs(r.y) < cosElevation;
        expected += covered;
        const auto& px = g.pixels[std::size_t(j) * w + i];
        REQUIRE((px.normal.w == 1.0f) == covered);
        if (!covered) continue;
        CHECK(xyz(px.normal) == glm::dvec3(0, 0, 1));
        CHECK(xyz(px.tangent) == glm::dvec3(1, 0, 0));
        CHECK(glm::dot(xyz(px.normal), xyz(px.view)) == doctest::Approx(cosElevation).epsilon(1e-6));
      }
    CHECK(g.objectPixelCount() == std::size_t(expected));
    CHECK(expected > 0);
    checkFrames(g, camera);
  }
  // Seen from behind, the plane is two-sided: the normal is -Z, towards the viewer.
  const GBuffer back = makeGBuffer("plane", {180, 10, 1}, 16, 16);
  CHECK(back.objectPixelCount() > 100);
  for (const auto& px : back.pixels)
    if (px.normal.w == 1.0f) CHECK(xyz(px.normal) == glm::dvec3(0, 0, -1));
  // Edge-on it covers nothing.
  CHECK(makeGBuffer("plane", {0, 90, 1}, 16, 16).objectPixelCount() == 0);
}

TEST_CASE("rasterizer: a UV-sphere OBJ approximates the analytic sphere within its tessellation error") {
  ScratchDir dir;
  const auto withNormals = dir.file("uv_normals.obj"), without = dir.file("uv.obj");
  std::ofstream(withNormals) << uvSphereObj(96, 48, true);
  std::ofstream(without) << uvSphereObj(96, 48, false);
  // Bands of h = 2 pi / 96 rad. Interpolating exact vertex normals errs by O(h^2) (measured: at most 0.003
  // rad, 0.0006 on average); area-weighted normals of the split quads by O(h) (0.028 and 0.005). Inside r <
  // 0.95, away from the silhouette where the mesh's hit point moves against the sphere's.
  const double h = 2.0 * kPi / 96.0;
  for (const CameraSpec camera : {CameraSpec{}, CameraSpec{40, 30, 1.3}, CameraSpec{-100, -60, 0.8}}) {
    for (const auto& path : {withNormals, without}) {
      CAPTURE(path.filename().string());
      CAPTURE(camera.azimuthDeg);
      const int size = 96;
      WarningCapture poleSlivers;  // the quads at the poles have a zero-area half
      const GBuffer mesh = makeGBuffer(path.string(), camera, size, size);
      const GBuffer sphere = makeSphereGBuffer(size, size, camera);
      int compared = 0, coverageMismatch = 0;
      double worst = 0.0, sum = 0.0;
      for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
          const std::size_t p = std::size_t(j) * size + i;
          const CameraRay r = cameraFrame(camera).onPlane(pixelToImagePlane(i, j, size, size));
          const double radius = std::sqrt(r.x * r.x + r.y * r.y);
          if ((mesh.pixels[p].normal.w == 1.0f) != (sphere.pixels[p].normal.w == 1.0f)) {
            ++coverageMismatch;
            CHECK(radius >
                  0.99);  // the polygon's silhouette is inside the sphere's by at most 1 - cos(pi/96)
          }
          if (radius >= 0.95 || sphere.pixels[p].normal.w == 0.0f) continue;
          const double angle =
              std::acos(std::min(1.0, glm::dot(xyz(mesh.pixels[p].normal), xyz(sphere.pixels[p].normal))));
          worst = std::max(worst, angle);
          sum += angle;
          ++compared;
        }
      INFO("worst normal error " << worst << " rad, mean " << sum / compared << ", coverage mismatches "
                                 << coverageMismatch);
      CHECK(compared > 3000);
      const bool fileNormals = path == withNormals;
      CHECK(worst < (fileNormals ? h * h : h / 2));
      CHECK(sum / compared < (fileNormals ? h * h / 4 : h / 10));
      checkFrames(mesh, camera);
    }
  }
}

TEST_CASE("rasterizer: nearest hit, two-sided triangles, clockwise files, bent normals at silhouettes") {
  // Two squares covering the image: z = 0 with normal +X-ish and z = 0.5 with normal +Z; the nearer wins.
  TriMesh layers;
  layers.positions = {{-2, -2, 0},   {2, -2, 0},   {2, 2, 0},   {-2, 2, 0},
                      {-2, -2, 0.5}, {2, -2, 0.5}, {2, 2, 0.5}, {-2, 2, 0.5}};
  layers.normals = {{0.6, 0, 0.8}, {0.6, 0, 0.8}, {0.6, 0, 0.8}, {0.6, 0, 0.8},
                    {0, 0, 1},     {0, 0, 1},     {0, 0, 1},     {0, 0, 1}};
  layers.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  for (const auto& px : rasterizeMesh(layers, {}, 8, 8).pixels) CHECK(xyz(px.normal) == glm::dvec3(0, 0, 1));
  // From -Z (azimuth 180) the z = 0 square is the nearer one, seen from behind: its normals are negated.
  for (const auto& px : rasterizeMesh(layers, {180, 0, 1}, 8, 8).pixels)
    CHECK(glm::length(xyz(px.normal) - glm::dvec3(-0.6, 0, -0.8)) < 1e-6);

  // Clockwise winding with normals towards the viewer: the front is the normals' side, not the winding's.
  TriMesh clockwise = layers;
  clockwise.triangles = {{4, 6, 5}, {4, 7, 6}};
  for (const auto& px : rasterizeMesh(clockwise, {}, 8, 8).pixels)
    CHECK(xyz(px.normal) == glm::dvec3(0, 0, 1));

  // A triangle facing the viewer whose vertex normals lean away on one side: where n . wo <= 0 the normal is
  // bent in the plane of n and wo to n . wo = kBentNormalViewCosine; elsewhere it is the interpolated one.
  TriMesh leaning;
  leaning.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  leaning.normals = {glm::normalize(glm::dvec3(-1, 0, -0.5)), glm::normalize(glm::dvec3(1, 0, 1)), {0, 0, 1}};
  leaning.triangles = {{0, 1, 2}};
  const int size = 64;
  const GBuffer g = rasterizeMesh(leaning, {}, size, size);
  int bent = 0, kept = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const auto& px = g.pixels[std::size_t(j) * size + i];
      if (px.normal.w == 0.0f) continue;
      // The interpolated normal at this pixel centre, from its barycentrics.
      const CameraRay r = pixelToImagePlane(i, j, size, size);
      const double b2 = (r.y + 1.0) / 2.0, b1 = (r.x + 1.0 - b2) / 2.0, b0 = 1.0 - b1 - b2;
      const glm::dvec3 n =
          glm::normalize(b0 * leaning.normals[0] + b1 * leaning.normals[1] + b2 * leaning.normals[2]);
      const glm::dvec3 actual = xyz(px.normal);
      if (n.z > 0.0) {
        ++kept;
        CHECK(glm::length(actual - n) < 1e-5);
      } else {
        ++bent;
        CHECK(actual.z == doctest::Approx(kBentNormalViewCosine).epsilon(1e-4));
        CHECK(std::abs(glm::dot(actual, glm::cross(n, glm::dvec3(0, 0, 1)))) <
              1e-5);  // in the plane of n, wo
        CHECK(glm::dot(actual, n) > 0.0);
      }
    }
  CHECK(bent > 20);
  CHECK(kept > 20);
  checkFrames(g, {});
}

TEST_CASE("rasterizer: no pixel falls through the edges shared by many thin triangles") {
  // The square [-0.9, 0.9]^2 split into triangles around jittered interior points: every pixel centre inside
  // it must be covered exactly as by the square itself.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  TriMesh mesh;
  const int n = 23;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) {
      const bool inner = x > 0 && x < n && y > 0 && y < n;
      const double step = 1.8 / n;
      mesh.positions.emplace_back(-0.9 + step * (x + (inner ? jitter(rng) : 0.0)),
                                  -0.9 + step * (y + (inner ? jitter(rng) : 0.0)), 0.0);
      mesh.normals.emplace_back(0, 0, 1);
    }
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const std::uint32_t a = y * (n + 1) + x, b = a + 1, c = a + n + 2, d = a + n + 1;
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  const int size = 200;
  const GBuffer straight = rasterizeMesh(mesh, {}, size, size);
  int holes = 0, expected = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const CameraRay r = pixelToImagePlane(i, j, size, size);
      const bool inside = std::abs(r.x) < 0.9 && std::abs(r.y) < 0.9;
      expected += inside;
      holes += inside && straight.pixels[std::size_t(j) * size + i].normal.w == 0.0f;
    }
  CHECK(holes == 0);
  CHECK(straight.objectPixelCount() == std::size_t(expected));
  // Seen from an orbit the square is a sheared parallelogram: image point (X, Y) shows the plane's point
  // x = X / cos(a), y = (Y + x sin(e) sin(a)) / cos(e).
  const double a = 17.0 * kPi / 180.0, e = 23.0 * kPi / 180.0;
  const GBuffer g = rasterizeMesh(mesh, {17, 23, 1}, size, size);
  int rotatedHoles = 0, rotatedInside = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const CameraRay r = pixelToImagePlane(i, j, size, size);
      const double x = r.x / std::cos(a), y = (r.y + x * std::sin(e) * std::sin(a)) / std::cos(e);
      if (std::abs(x) > 0.9 - 1e-9 || std::abs(y) > 0.9 - 1e-9) continue;
      ++rotatedInside;
      rotatedHoles += g.pixels[std::size_t(j) * size + i].normal.w == 0.0f;
    }
  CHECK(rotatedInside > 20000);
  CHECK(rotatedHoles == 0);

  // A fan whose vertices sit on pixel centres: its shared edges pass through dozens of pixel centres, which
  // edge tests that exclude the edge, or that round differently on its two sides, would leave uncovered.
  const auto centre = [&](int i, int j) {
    const CameraRay r = pixelToImagePlane(i, j, size, size);
    return glm::dvec3(r.x, r.y, 0.0);
  };
  TriMesh fan;
  fan.positions.push_back(centre(93, 104));
  std::vector<std::pair<int, int>> ring;
  for (int k = -60; k < 60; k += 7) ring.emplace_back(100 + k, 40);
  for (int k = -60; k < 60; k += 7) ring.emplace_back(160, 100 + k);
  for (int k = 60; k > -60; k -= 7) ring.emplace_back(100 + k, 160);
  for (int k = 60; k > -60; k -= 7) ring.emplace_back(40, 100 + k);
  for (const auto& [i, j] : ring) fan.positions.push_back(centre(i, j));
  fan.normals.assign(fan.positions.size(), glm::dvec3(0, 0, 1));
  for (std::uint32_t k = 0; k < ring.size(); ++k)
    fan.triangles.push_back(
        {0, 1 + (k + 1) % std::uint32_t(ring.size()), 1 + k});  // clockwise in pixels = CCW in y-up
  const GBuffer fanBuffer = rasterizeMesh(fan, {}, size, size);
  int fanHoles = 0, outside = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const bool covered = fanBuffer.pixels[std::size_t(j) * size + i].normal.w == 1.0f;
      if (i > 40 && i < 160 && j > 40 && j < 160) fanHoles += !covered;
      if (i < 40 || i > 160 || j < 40 || j > 160) outside += covered;
    }
  CHECK(fanHoles == 0);
  CHECK(outside == 0);
}

TEST_CASE("objects: unknown names and files are reported") {
  CHECK(contains(errorMessage([] { makeGBuffer("cube", {}, 8, 8); }),
                 "unknown object 'cube'; valid: sphere, plane, teapot"));
  CHECK(contains(errorMessage([] { makeGBuffer("/no/such/mesh.obj", {}, 8, 8); }),
                 "/no/such/mesh.obj: no such file"));
  CHECK(contains(errorMessage([] { makeGBuffer("plane", {0, 0, -1}, 8, 8); }), "zoom -1"));
}
