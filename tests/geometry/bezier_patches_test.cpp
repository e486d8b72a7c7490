// Tests of the Bézier patch reader, evaluator and tessellator (engine/geometry/bezier_patches.h) and of the
// teapot they make: the data file is Newell's (its symmetries catch transcription errors), the tessellation
// is welded with unit outward normals, and assets/teapot.obj is what `iblx make-teapot` writes.
#include "engine/core/assets.h"
#include "engine/geometry/bezier_patches.h"
#include "engine/geometry/gbuffer.h"
#include "engine/geometry/obj_file.h"
#include "engine/geometry/rasterizer.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

using namespace iblx;
using namespace iblx::test;

namespace {

BezierPatchSet newellPatches() {
  return readBezierPatches(assetPath("teapot_patches.txt"));
}

std::array<glm::dvec3, 16> controlPointsOf(const BezierPatchSet& set, std::size_t patch) {
  std::array<glm::dvec3, 16> points;
  for (int k = 0; k < 16; ++k) points[k] = set.controlPoints[set.patches[patch][k]];
  return points;
}

bool near(glm::dvec3 a, glm::dvec3 b, double eps) {
  return glm::length(a - b) < eps;
}

// Pairs of vertices closer than `distance` (a sort along x keeps this O(n log n) for spread-out points).
std::vector<std::pair<std::uint32_t, std::uint32_t>> closePairs(const TriMesh& mesh, double distance) {
  std::vector<std::uint32_t> order(mesh.positions.size());
  for (std::uint32_t v = 0; v < order.size(); ++v) order[v] = v;
  std::sort(order.begin(), order.end(),
            [&](auto a, auto b) { return mesh.positions[a].x < mesh.positions[b].x; });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::size_t a = 0; a < order.size(); ++a)
    for (std::size_t b = a + 1; b < order.size(); ++b) {
      if (mesh.positions[order[b]].x - mesh.positions[order[a]].x > distance) break;
      if (glm::length(mesh.positions[order[a]] - mesh.positions[order[b]]) <= distance)
        pairs.emplace_back(order[a], order[b]);
    }
  return pairs;
}

}  // namespace

TEST_CASE("teapot patches: Newell's 32 patches on 306 control points, as transcribed") {
  const BezierPatchSet set = newellPatches();
  REQUIRE(set.patches.size() == 32);
  REQUIRE(set.controlPoints.size() == 306);
  CHECK(set.controlPoints[0] == glm::dvec3(1.4, 0.0, 2.4));
  CHECK(set.controlPoints[305] == glm::dvec3(1.425, -0.798, 0.0));
  // Rim (patches 1-4), body (5-12), lid (21-28) and bottom (29-32) come in groups of 4, each a quarter turn
  // about Newell's z axis of the one before; the handle (13-16) and spout (17-20) in pairs mirrored in y = 0
  // (columns reversed). Any mistyped coordinate breaks one of these.
  auto quarterTurn = [](glm::dvec3 p, int sign) { return glm::dvec3(sign * p.y, -sign * p.x, p.z); };
  for (const std::size_t group : {0u, 4u, 8u, 20u, 24u, 28u})
    for (std::size_t k = 0; k < 3; ++k) {
      CAPTURE(group + k + 1);
      const auto a = controlPointsOf(set, group + k), b = controlPointsOf(set, group + k + 1);
      const int sign = group == 28 ? -1 : 1;  // the bottom turns the other way
      for (int i = 0; i < 16; ++i) CHECK(near(quarterTurn(a[i], sign), b[i], 1e-12));
    }
  for (const std::size_t first : {12u, 14u, 16u, 18u}) {
    CAPTURE(first + 1);
    const auto a = controlPointsOf(set, first), b = controlPointsOf(set, first + 1);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        const glm::dvec3 p = a[4 * r + 3 - c];
        CHECK(near(glm::dvec3(p.x, -p.y, p.z), b[4 * r + c], 1e-12));
      }
  }
}

TEST_CASE("bezier patches: corners interpolate, a bilinear patch is exact, derivatives match differences") {
  BezierPatchSet set;
  // Control points on the plane z = x + 2y at (c/3, r/3): the patch is that plane with P(u, v) = (u, v, u +
  // 2v).
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) set.controlPoints.emplace_back(c / 3.0, r / 3.0, c / 3.0 + 2.0 * r / 3.0);
  set.patches.push_back({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15});
  for (const double u : {0.0, 0.3, 1.0})
    for (const double v : {0.0, 0.7, 1.0}) {
      const PatchPoint p = evaluateBicubic(set, 0, u, v);
      CHECK(near(p.position, {u, v, u + 2 * v}, 1e-14));
      CHECK(near(p.du, {1, 0, 1}, 1e-13));
      CHECK(near(p.dv, {0, 1, 2}, 1e-13));
      CHECK(near(patchNormal(set, 0, u, v), glm::normalize(glm::dvec3(-1, -2, 1)), 1e-13));
    }
  // On a teapot patch: corners are control points; derivatives agree with central differences.
  const BezierPatchSet teapot = newellPatches();
  const auto cp = controlPointsOf(teapot, 16);
  CHECK(near(evaluateBicubic(teapot, 16, 0, 0).position, cp[0], 1e-15));
  CHECK(near(evaluateBicubic(teapot, 16, 1, 1).position, cp[15], 1e-15));
  const double h = 1e-6;
  const PatchPoint p = evaluateBicubic(teapot, 16, 0.4, 0.6);
  const glm::dvec3 du = (evaluateBicubic(teapot, 16, 0.4 + h, 0.6).position -
                         evaluateBicubic(teapot, 16, 0.4 - h, 0.6).position) /
                        (2 * h);
  const glm::dvec3 dv = (evaluateBicubic(teapot, 16, 0.4, 0.6 + h).position -
                         evaluateBicubic(teapot, 16, 0.4, 0.6 - h).position) /
                        (2 * h);
  CHECK(near(p.du, du, 1e-7));
  CHECK(near(p.dv, dv, 1e-7));
  // At the lid's pole (patch 21, v = 0: its first row is one point) the normal is the limit: straight up.
  CHECK(near(patchNormal(teapot, 20, 0.5, 0.0), {0, 0, 1}, 1e-3));
  CHECK(near(patchNormal(teapot, 28, 0.3, 0.0), {0, 0, -1}, 1e-3));
}

TEST_CASE("teapot tessellation: welded, unit outward normals, poles collapsed, fits the unit sphere") {
  BezierPatchSet set = newellPatches();
  zUpToYUp(set);
  for (const int n : {4, 12}) {
    CAPTURE(n);
    const TriMesh mesh = tessellateBezierPatches(set, n);
    // 2 N^2 triangles per patch, less the N at each collapsed edge of the 4 lid-top and 4 bottom patches.
    CHECK(mesh.triangles.size() == std::size_t(32 * 2 * n * n - 8 * n));
    TriMesh copy = mesh;
    CHECK(dropDegenerateTriangles(copy) == 0);
    // Welding: no two vertices within 1e-9 except where two surfaces only touch with normals on opposite
    // sides: the single point where the handle's lower end meets the body.
    const auto pairs = closePairs(mesh, 1e-9);
    CHECK(pairs.size() == 1);
    for (const auto& [a, b] : pairs) {
      CHECK(glm::dot(mesh.normals[a], mesh.normals[b]) < 0.0);
      CHECK(near(mesh.positions[a], {-2.0, 0.9, 0.0}, 1e-12));
    }
    // The poles are one vertex each (lid top and bottom centre).
    int lidTop = 0, bottom = 0;
    for (const auto& p : mesh.positions)
      lidTop += near(p, {0, 3.15, 0}, 1e-9), bottom += near(p, {0, 0, 0}, 1e-9);
    CHECK(lidTop == 1);
    CHECK(bottom == 1);
    // Seam vertices are shared: the ring where the upper body patches meet the lower ones (y = 0.9, radius 2)
    // is inside one continuous grid, so each of its vertices is used by 6 triangles (3 if unwelded).
    std::vector<int> valence(mesh.positions.size(), 0);
    for (const auto& t : mesh.triangles)
      for (const auto v : t) ++valence[v];
    int ring = 0, ringShared = 0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::dvec3& p = mesh.positions[v];
      if (std::abs(p.y - 0.9) > 1e-9 || std::abs(std::hypot(p.x, p.z) - 2.0) > 1e-2 ||
          near(p, {-2, 0.9, 0}, 1e-9))
        continue;
      ++ring;
      ringShared += valence[v] == 6;
    }
    CHECK(ring == 4 * n - 1);  // 4 patches of N cells around, less the handle's corner
    CHECK(ringShared == ring);
    int bad = 0, outward = 0, body = 0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::dvec3 &p = mesh.positions[v], &nv = mesh.normals[v];
      bad += std::abs(glm::length(nv) - 1.0) > 1e-12;
      // Outward on the body (away from the vertical axis), clear of the spout (x > 1.7) and the handle's ends
      // (x < -1.4, |z| < 0.3).
      const double radial = std::hypot(p.x, p.z);
      const bool handle = p.x < -1.4 && std::abs(p.z) < 0.35;
      if (p.y > 0.3 && p.y < 2.3 && radial > 1.2 && std::abs(p.x) < 1.6 && !handle) {
        ++body;
        outward += glm::dot(nv, glm::dvec3(p.x, 0, p.z)) > 0.0;
      }
    }
    CHECK(bad == 0);
    CHECK(body > 20);
    CHECK(outward == body);
    // Windings agree with the normals (the rasterizer does not need it; the OBJ should be conventional).
    int agree = 0;
    for (const auto& t : mesh.triangles)
      agree += glm::dot(triangleAreaNormal(mesh, t),
                        mesh.normals[t[0]] + mesh.normals[t[1]] + mesh.normals[t[2]]) > 0;
    CHECK(agree == int(mesh.triangles.size()));
  }
}

TEST_CASE("teapot: assets/teapot.obj is make-teapot's output and loads centred with bounding radius 1") {
  BezierPatchSet set = newellPatches();
  zUpToYUp(set);
  const TriMesh fresh = tessellateBezierPatches(set, 12);
  const TriMesh stored = readObj(teapotObjPath());
  REQUIRE(stored.positions.size() == fresh.positions.size());
  CHECK(stored.triangles == fresh.triangles);
  double worst = 0.0;
  for (std::size_t v = 0; v < fresh.positions.size(); ++v)
    worst = std::max({worst, glm::length(stored.positions[v] - fresh.positions[v]),
                      glm::length(stored.normals[v] - fresh.normals[v])});
  CHECK(worst < 1e-6);  // 7 significant digits

  const TriMesh loaded = loadObjectMesh("teapot");
  glm::dvec3 lo(1e9), hi(-1e9);
  double radius = 0.0;
  for (const auto& p : loaded.positions)
    lo = glm::min(lo, p), hi = glm::max(hi, p), radius = std::max(radius, glm::length(p));
  CHECK(radius == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(glm::length(lo + hi) < 1e-12);
  CHECK(closePairs(loaded, 1e-9).size() == 1);

  // The teapot's G-buffer: valid frames, one shading point per covered pixel, n . wo > 0 everywhere.
  const auto start = std::chrono::steady_clock::now();
  const GBuffer g = makeGBuffer("teapot", {30, 20, 1}, 256, 256);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  MESSAGE("teapot G-buffer 256x256 (load + raster): " << seconds << " s");
  CHECK(g.objectPixelCount() > 256 * 256 / 5);
  const glm::dvec3 back = cameraFrame({30, 20, 1}).back;
  int bad = 0;
  for (const auto& px : g.pixels)
    if (px.normal.w == 1.0f) {
      const glm::dvec3 n(px.normal.x, px.normal.y, px.normal.z), t(px.tangent.x, px.tangent.y, px.tangent.z);
      bad += std::abs(glm::length(n) - 1.0) > 1e-6 || std::abs(glm::dot(n, t)) > 1e-6 ||
             !(glm::dot(n, back) > 0.0) || !std::isfinite(n.x + t.x);
    }
  CHECK(bad == 0);
}

TEST_CASE("bezier patch files: bad files give the file, the line and the problem") {
  ScratchDir dir;
  struct Case {
    std::string name, text, expected;
  };
  const std::string sixteen = "1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 1\n";
  const Case cases[] = {
      {"empty.txt", "# nothing\n", "empty.txt:1: the file ends where 'patches N' was expected"},
      {"count.txt", "patches x\n", "count.txt:1: expected 'patches N'"},
      {"short.txt", "patches 1\n1 2 3\n", "short.txt:2: a patch needs 16 control-point indices"},
      {"missing.txt", "patches 2\n" + sixteen, "missing.txt:2: the file ends where patch 2 was expected"},
      {"vertex.txt", "patches 1\n" + sixteen + "vertices 1\n1 2\n", "vertex.txt:4: expected three numbers"},
      {"range.txt", "patches 1\n1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 7\nvertices 1\n0 0 0\n",
       "range.txt:2: index 7 is not in [1, 1]"},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name);
    const auto path = dir.file(c.name);
    std::ofstream(path) << c.text;
    CHECK(contains(errorMessage([&] { readBezierPatches(path); }), c.expected));
  }
  CHECK(contains(errorMessage([&] { readBezierPatches(dir.file("none.txt")); }), "none.txt: no such file"));
}
