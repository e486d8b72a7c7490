// Tests of the OBJ reader and writer (engine/geometry/obj_file.h): small files written here, with and without
// normals, and every class of bad file with its one-line message.
#include "engine/geometry/obj_file.h"
#include "tests/io/scratch_files.h"

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>

using namespace iblx;
using namespace iblx::test;

namespace {

std::filesystem::path writeText(const ScratchDir& dir, const std::string& name, const std::string& text) {
  const auto path = dir.file(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

bool near(glm::dvec3 a, glm::dvec3 b, double eps = 1e-12) {
  return glm::length(a - b) < eps;
}

// The index of the mesh vertex at position p (there must be exactly one).
std::uint32_t vertexAt(const TriMesh& mesh, glm::dvec3 p) {
  std::uint32_t found = 0, count = 0;
  for (std::uint32_t v = 0; v < mesh.positions.size(); ++v)
    if (near(mesh.positions[v], p)) found = v, ++count;
  REQUIRE(count == 1);
  return found;
}

}  // namespace

TEST_CASE("obj: without normals, vertex normals are the area-weighted sums of the face normals") {
  // Two triangles on the edge from (0,0,0) to (0,1,0): one in the xy-plane with (p1-p0) x (p2-p0) = (0,0,1),
  // one in the yz-plane with (2,0,0). The edge's vertices get normalize(2,0,1), the others their face's.
  ScratchDir dir;
  const auto path = writeText(dir, "hinge.obj",
                              "# a hinge\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 -2\n"
                              "vt 0 0\ng faces\nf 1 2 3\nf 1/1 4 3\n");
  const TriMesh mesh = readObj(path);
  CHECK(mesh.triangles.size() == 2);
  REQUIRE(mesh.positions.size() == 4);
  REQUIRE(mesh.normals.size() == 4);
  const glm::dvec3 shared = glm::normalize(glm::dvec3(2, 0, 1));
  CHECK(near(mesh.normals[vertexAt(mesh, {0, 0, 0})], shared));
  CHECK(near(mesh.normals[vertexAt(mesh, {0, 1, 0})], shared));
  CHECK(near(mesh.normals[vertexAt(mesh, {1, 0, 0})], {0, 0, 1}));
  CHECK(near(mesh.normals[vertexAt(mesh, {0, 0, -2})], {1, 0, 0}));
}

TEST_CASE("obj: the file's normals are used (normalized) when every face vertex has one") {
  ScratchDir dir;
  // A quad (triangulated into two triangles) with a normal of length 2 and negative (relative) indices; the
  // same position with two normals becomes two vertices.
  const auto path = writeText(dir, "quad.obj",
                              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 2\nvn 0 0.6 0.8\n"
                              "f 1//1 2//1 3//1 4//1\nf -4//2 -3//2 -2//2\n");
  const TriMesh mesh = readObj(path);
  CHECK(mesh.triangles.size() == 3);
  CHECK(mesh.positions.size() == 4 + 3);
  int tilted = 0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    CHECK(std::abs(glm::length(mesh.normals[v]) - 1.0) < 1e-12);
    tilted += near(mesh.normals[v], {0, 0.6, 0.8});
  }
  CHECK(tilted == 3);
  // The triangulated quad covers it: twice its area in total.
  double area = 0.0;
  for (std::size_t t = 0; t < 2; ++t) area += glm::length(triangleAreaNormal(mesh, mesh.triangles[t]));
  CHECK(area == doctest::Approx(2.0));

  // One face without normals: all normals are computed (the file's would leave that face without).
  const auto mixed =
      writeText(dir, "mixed.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvn 1 0 0\nf 1//1 2//1 3//1\nf 1 3 2\n");
  const TriMesh computed = readObj(mixed);
  for (const auto& n : computed.normals) CHECK_FALSE(near(n, {1, 0, 0}));
}

TEST_CASE("obj: write and read back; loadObjMesh centres on the bounding box and fits the unit sphere") {
  ScratchDir dir;
  TriMesh mesh;
  mesh.positions = {{1, 2, 3}, {5, 2, 3}, {5, 4, 3}, {1, 4, 7}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  computeSmoothNormals(mesh);
  const auto path = dir.file("round.obj");
  writeObj(path, mesh, "first line\nsecond line");
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  CHECK(first == "# first line");
  const TriMesh back = readObj(path);
  REQUIRE(back.positions.size() == mesh.positions.size());
  CHECK(back.triangles == mesh.triangles);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    CHECK(near(back.positions[v], mesh.positions[v], 1e-6));
    CHECK(near(back.normals[v], mesh.normals[v], 1e-6));
  }
  const TriMesh fitted = loadObjMesh(path);
  // Box centre (3, 3, 5); the farthest corner is at distance sqrt(4 + 1 + 4) = 3.
  CHECK(near(fitted.positions[0], glm::dvec3(-2, -1, -2) / 3.0, 1e-6));
  double radius = 0.0;
  for (const auto& p : fitted.positions) radius = std::max(radius, glm::length(p));
  CHECK(radius == doctest::Approx(1.0));
}

TEST_CASE("obj: faces of zero area are dropped with one warning that counts them") {
  ScratchDir dir;
  const auto path =
      writeText(dir, "sliver.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 2 2 3\n");
  WarningCapture warnings;
  const TriMesh mesh = readObj(path);
  CHECK(mesh.triangles.size() == 1);
  REQUIRE(warnings.messages.size() == 1);
  CHECK(contains(warnings.messages[0], "sliver.obj: 2 of 3 triangles have zero area"));

  const auto zero =
      writeText(dir, "zero_normal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n");
  WarningCapture more;
  const TriMesh smooth = readObj(zero);
  REQUIRE(more.messages.size() == 1);
  CHECK(contains(more.messages[0], "normal 1 is zero"));
  CHECK(near(smooth.normals[0], {0, 0, 1}));
}

TEST_CASE("obj: every kind of bad file gives one line naming the file and the problem") {
  ScratchDir dir;
  std::filesystem::create_directory(dir.file("folder.obj"));
  struct Case {
    std::string name, text, expected;
  };
  const Case cases[] = {
      {"bad_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "bad_face.obj:4: bad 'f' line"},
      {"letters.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n", "letters.obj:4: bad 'f' line"},
      {"not_number.obj", "v 0 0 0\nv 1 abc 0\n", "not_number.obj:2: 'abc' is not a decimal number"},
      // strtod reads hexadecimal, tinyobjloader read it as 0.
      {"hex.obj", "v 0 0 0\nv 0x1p3 0 0\nv 0 1 0\nf 1 2 3\n", "hex.obj:2: '0x1p3' is not a decimal number"},
      // A relative index before the first normal read as "no normal" and was accepted.
      {"relative_normal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//-9 2//-1 3//-1\n",
       "relative_normal.obj:5: relative index -9 counts back past the first 'vn' line (1 so far)"},
      {"relative_vertex.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n",
       "relative_vertex.obj:3: relative index -3 counts back past the first 'v' line (2 so far)"},
      {"short.obj", "v 0 0\n", "short.obj:1: 'v' needs three numbers"},
      {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "nan.obj:2: coordinate 'nan' is not finite"},
      {"huge.obj", "v 0 0 0\nv 1e999 0 0\n", "huge.obj:2: coordinate '1e999' is not finite"},
      {"inf_normal.obj", "v 0 0 0\nvn 0 inf 0\n", "inf_normal.obj:2: coordinate 'inf' is not finite"},
      {"overflow.obj", "v -1e308 0 0\nv 1e308 0 0\nv 0 1 0\nf 1 2 3\n",
       "overflow.obj: coordinates too large"},
      {"empty.obj", "", "empty.obj: no faces"},
      {"points.obj", "v 0 0 0\nv 1 0 0\np 1 2\nl 1 2\n", "points.obj: no faces"},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n",
       "range.obj: face 2 refers to vertex 9 but the file has 3"},
      {"normal_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n",
       "normal_range.obj: face 1 refers to normal 2 but the file has 1"},
      {"point.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n", "point.obj: all vertices are at one point"},
      {"line.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n", "line.obj: every face has zero area"},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name);
    const auto path = writeText(dir, c.name, c.text);
    const std::string message = errorMessage([&] { readObj(path); });
    CHECK(contains(message, c.expected));
    CHECK(contains(message, path.string()));
    CHECK(message.find('\n') == std::string::npos);
  }
  CHECK(contains(errorMessage([&] { readObj(dir.file("missing.obj")); }), "missing.obj: no such file"));
  CHECK(contains(errorMessage([&] { readObj(dir.file("folder.obj")); }), "folder.obj: it is a directory"));
  // Random bytes: an iblx::Error naming the file, never a crash.
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const auto path = dir.file("random" + std::to_string(seed) + ".obj");
    writeBytes(path, randomBytes(2000, seed));
    CHECK(contains(errorMessage([&] { readObj(path); }), path.string()));
  }
}

TEST_CASE("obj: a face index beyond int is out of range, not wrapped") {
  ScratchDir dir;
  // 4294967299 = 2^32 + 3: tinyobjloader alone reads it as vertex 3 and the mesh renders.
  for (const char* index : {"4294967299", "-4294967299", "2147483648", "99999999999999999999999"}) {
    CAPTURE(index);
    const auto path =
        writeText(dir, "wrap.obj", std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 ") + index + "\n");
    CHECK(contains(errorMessage([&] { readObj(path); }),
                   "wrap.obj:4: index " + std::string(index) + " is out of range"));
  }
  const auto normals =
      writeText(dir, "n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//4294967297 2//1 3//1\n");
  CHECK(contains(errorMessage([&] { readObj(normals); }), "n.obj:5: index 4294967297 is out of range"));
}

TEST_CASE("obj: lines ended by a lone CR are checked too (tinyobjloader reads them as lines)") {
  ScratchDir dir;
  const auto nan = writeText(dir, "cr_nan.obj", "v 0 0 0\rv 1 0 0\rv 0 1 0\rv nan 0 0\rf 1 2 3\r");
  CHECK(contains(errorMessage([&] { readObj(nan); }), "cr_nan.obj:4: coordinate 'nan' is not finite"));
  const auto wrap = writeText(dir, "cr_wrap.obj", "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 4294967299\r");
  CHECK(contains(errorMessage([&] { readObj(wrap); }), "cr_wrap.obj:4: index 4294967299 is out of range"));
  const auto crlf = writeText(dir, "crlf.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 7\r\n");
  CHECK(contains(errorMessage([&] { readObj(crlf); }), "crlf.obj: face 1 refers to vertex 7"));
}
