// OBJ reading and writing (engine/geometry/obj_file.h). tinyobjloader parses and triangulates; this file adds
// the checks it leaves out (numbers on `v`/`vn` lines, index ranges, finiteness, extent) so that every bad
// file ends in one line naming it.
#include "engine/geometry/obj_file.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"
#include "engine/core/log.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <sstream>

namespace iblx {
namespace {

std::string prefix(const std::filesystem::path& path, int line = 0) {
  std::string text = path.string();
  if (line > 0)
    text.append(1, ':').append(std::to_string(line));  // not ":" + string: GCC 12's false -Wrestrict
  return text.append(": ");
}

// tinyobjloader's parse error as one line "FILE:LINE: problem": its messages end in newlines and give the
// line as "line N." inside the text.
std::string parseError(const std::filesystem::path& path, const std::string& message) {
  std::string text = message.substr(0, message.find('\n'));
  while (!text.empty() && (text.back() == '\r' || text.back() == ' ')) text.pop_back();
  int line = 0;
  if (const auto at = text.rfind("line "); at != std::string::npos) line = std::atoi(text.c_str() + at + 5);
  if (text.rfind("Failed parse `f' line", 0) == 0)
    return prefix(path, line) +
           "bad 'f' line: vertex indices must be non-zero integers (1-based, negative counts back)";
  return prefix(path, line) + (text.empty() ? std::string("cannot be parsed") : "tinyobjloader: " + text);
}

// tinyobjloader parses indices into int with wrap-around (4294967299 becomes 3), so each index of an element
// line is checked here to fit an int before it parses them.
// A negative (relative) index counts back from the last element of its kind defined so far (`defined`: 'v',
// 'vt' and 'vn' lines before this one); one that counts back past the first is refused here, as tinyobjloader
// turns it into a negative index that reads as "no normal" (f 1//-9 with one normal was accepted).
void checkIndices(const std::filesystem::path& path, int number, std::istringstream& tokens,
                  const std::array<long long, 3>& defined) {
  constexpr const char* kKinds[3] = {"v", "vt", "vn"};
  for (std::string token; tokens >> token;) {
    if (token[0] == '#') return;
    int component = 0;
    for (std::size_t begin = 0; begin <= token.size(); ++component) {
      const std::size_t end = std::min(token.find('/', begin), token.size());
      const std::string index = token.substr(begin, end - begin);
      if (!index.empty()) {
        errno = 0;
        char* stop = nullptr;
        const long long value = std::strtoll(index.c_str(), &stop, 10);
        if (stop == index.c_str() + index.size() &&
            (errno == ERANGE || value > std::numeric_limits<int>::max() ||
             value < -std::numeric_limits<int>::max()))
          throw Error(prefix(path, number) + "index " + index + " is out of range");
        if (stop == index.c_str() + index.size() && value < 0 && component < 3 &&
            -value > defined[std::size_t(component)])
          throw Error(prefix(path, number) + "relative index " + index + " counts back past the first '" +
                      kKinds[component] + "' line (" + std::to_string(defined[std::size_t(component)]) +
                      " so far)");
      }
      begin = end + 1;
    }
  }
}

// tinyobjloader reads a missing or malformed number on a `v` or `vn` line as 0 without a word, so the
// coordinates are checked here first: three numbers, each finite (strtod accepts "nan" and "inf").
void checkCoordinateLines(const std::filesystem::path& path, const std::string& text) {
  // Lines end as tinyobjloader ends them (its safeGetline): at "\n", "\r\n" or a lone "\r", so that a file
  // with old Mac line ends cannot hide a line from these checks.
  std::size_t pos = 0;
  std::array<long long, 3> defined{0, 0, 0};  // 'v', 'vt' and 'vn' lines so far
  for (int number = 1; pos < text.size(); ++number) {
    const std::size_t lineEnd = std::min(text.find_first_of("\r\n", pos), text.size());
    const std::string line = text.substr(pos, lineEnd - pos);
    pos = lineEnd + (lineEnd + 1 < text.size() && text[lineEnd] == '\r' && text[lineEnd + 1] == '\n' ? 2 : 1);
    std::istringstream tokens(line);
    std::string keyword;
    tokens >> keyword;
    if (keyword == "f" || keyword == "l" || keyword == "p") {
      checkIndices(path, number, tokens, defined);
      continue;
    }
    if (keyword == "vt") ++defined[1];
    if (keyword != "v" && keyword != "vn") continue;
    ++defined[keyword == "v" ? 0 : 2];
    for (int k = 0; k < 3; ++k) {
      std::string token;
      if (!(tokens >> token))
        throw Error(prefix(path, number) + "'" + keyword + "' needs three numbers (x y z)");
      char* end = nullptr;
      const double value = std::strtod(token.c_str(), &end);
      // strtod also reads hexadecimal ("0x1p3" is 8), which tinyobjloader reads as 0.
      if (end != token.c_str() + token.size() || token.find_first_of("xX") != std::string::npos)
        throw Error(prefix(path, number) + "'" + printableExcerpt(token) + "' is not a decimal number");
      if (!std::isfinite(value))
        throw Error(prefix(path, number) + "coordinate '" + token + "' is not finite");
    }
  }
}

}  // namespace

TriMesh readObj(const std::filesystem::path& path) {
  // tinyobjloader holds several copies of the text's worth of arrays: an eighth of the memory budget.
  const std::string text = readInputText(path, memoryBudgetBytes() / 8);
  checkCoordinateLines(path, text);

  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // From a string: `mtllib` is ignored, so no material file is looked for (iblx has its own BRDFs).
  if (!reader.ParseFromString(text, "", config)) throw Error(parseError(path, reader.Error()));
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const long vertexCount = long(attrib.vertices.size() / 3), normalCount = long(attrib.normals.size() / 3);

  // Every face vertex's indices, checked; the file's normals are used only when every face vertex has one.
  std::vector<tinyobj::index_t> corners;
  long face = 0;
  for (const auto& shape : reader.GetShapes()) {
    std::size_t offset = 0;
    for (const auto count : shape.mesh.num_face_vertices) {
      ++face;
      if (count == 3)
        for (std::size_t k = 0; k < 3; ++k) {
          const tinyobj::index_t& c = shape.mesh.indices[offset + k];
          if (c.vertex_index < 0 || c.vertex_index >= vertexCount)
            throw Error(prefix(path) + "face " + std::to_string(face) + " refers to vertex " +
                        std::to_string(long(c.vertex_index) + 1) + " but the file has " +
                        std::to_string(vertexCount) + " ('v' lines)");
          if (c.normal_index >= normalCount)
            throw Error(prefix(path) + "face " + std::to_string(face) + " refers to normal " +
                        std::to_string(long(c.normal_index) + 1) + " but the file has " +
                        std::to_string(normalCount) + " ('vn' lines)");
          corners.push_back(c);
        }
      offset += count;
    }
  }
  if (corners.empty()) throw Error(prefix(path) + "no faces ('f' lines with 3 or more vertices)");

  bool useFileNormals = true;
  for (const auto& c : corners) useFileNormals = useFileNormals && c.normal_index >= 0;
  if (useFileNormals)
    for (const auto& c : corners) {
      const double* n = &attrib.normals[3 * std::size_t(c.normal_index)];
      if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) {
        warn(prefix(path) + "normal " + std::to_string(c.normal_index + 1) +
             " is zero; smooth normals are computed instead of the file's");
        useFileNormals = false;
        break;
      }
    }

  // One mesh vertex per distinct (position, normal) pair, or per position when the normals are computed, in
  // the order of the file's 'v' lines (so a file written by writeObj reads back with its own numbering).
  auto keyOf = [&](const tinyobj::index_t& c) {
    return std::uint64_t(c.vertex_index) * std::uint64_t(normalCount + 1) +
           std::uint64_t(useFileNormals ? c.normal_index : 0);
  };
  std::vector<std::uint64_t> keys;
  keys.reserve(corners.size());
  for (const auto& c : corners) keys.push_back(keyOf(c));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  TriMesh mesh;
  for (const std::uint64_t key : keys) {
    const auto v = std::size_t(key / std::uint64_t(normalCount + 1)),
               n = std::size_t(key % std::uint64_t(normalCount + 1));
    mesh.positions.emplace_back(attrib.vertices[3 * v], attrib.vertices[3 * v + 1],
                                attrib.vertices[3 * v + 2]);
    if (useFileNormals)
      mesh.normals.push_back(glm::normalize(
          glm::dvec3(attrib.normals[3 * n], attrib.normals[3 * n + 1], attrib.normals[3 * n + 2])));
  }
  std::array<std::uint32_t, 3> triangle{};
  for (std::size_t k = 0; k < corners.size(); ++k) {
    triangle[k % 3] =
        std::uint32_t(std::lower_bound(keys.begin(), keys.end(), keyOf(corners[k])) - keys.begin());
    if (k % 3 == 2) mesh.triangles.push_back(triangle);
  }

  glm::dvec3 lo = mesh.positions[0], hi = mesh.positions[0];
  for (const auto& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double extent = glm::length(hi - lo);
  if (!(extent > 0.0)) throw Error(prefix(path) + "all vertices are at one point (the mesh has no extent)");
  if (!std::isfinite(extent)) throw Error(prefix(path) + "coordinates too large (the extent overflows)");

  const std::size_t faces = mesh.triangles.size();
  if (const std::size_t dropped = dropDegenerateTriangles(mesh)) {
    if (mesh.triangles.empty()) throw Error(prefix(path) + "every face has zero area (degenerate triangles)");
    warn(prefix(path) + std::to_string(dropped) + " of " + std::to_string(faces) +
         " triangles have zero area and are ignored");
  }
  if (!useFileNormals) computeSmoothNormals(mesh);
  return mesh;
}

TriMesh loadObjMesh(const std::filesystem::path& path) {
  TriMesh mesh = readObj(path);
  fitToUnitSphere(mesh);
  return mesh;
}

void writeObj(const std::filesystem::path& path, const TriMesh& mesh, const std::string& comment) {
  AtomicOutput output(path);
  std::ofstream& f = output.stream();
  f.precision(7);
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) f << "# " << line << "\n";
  for (const auto& p : mesh.positions) f << "v " << p.x << " " << p.y << " " << p.z << "\n";
  for (const auto& n : mesh.normals) f << "vn " << n.x << " " << n.y << " " << n.z << "\n";
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      f << (k == 0 ? "f " : " ") << t[k] + 1 << "//" << t[k] + 1 << (k == 2 ? "\n" : "");
  output.commit();
}

}  // namespace iblx
