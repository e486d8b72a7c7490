// Bicubic Bézier patches: reading, evaluation and welded tessellation (engine/geometry/bezier_patches.h).
#include "engine/geometry/bezier_patches.h"

#include "engine/core/error.h"
#include "engine/core/file_io.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <unordered_map>

namespace iblx {
namespace {

// Cubic Bernstein polynomials B_k(t) and their derivatives B_k'(t).
std::array<double, 4> bernstein(double t) {
  const double s = 1.0 - t;
  return {s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t};
}
std::array<double, 4> bernsteinDerivative(double t) {
  const double s = 1.0 - t;
  return {-3.0 * s * s, 3.0 * s * s - 6.0 * t * s, 6.0 * t * s - 3.0 * t * t, 3.0 * t * t};
}

// The non-comment lines of a patch file with their line numbers.
struct Line {
  int number = 0;
  std::istringstream tokens;
};

class LineReader {
 public:
  // The whole file is read first, within a bound: patch files are a few KiB, and a FIFO or device is refused.
  explicit LineReader(const std::filesystem::path& path)
      : path_(path), in_(readInputText(path, std::uint64_t(16) << 20)) {}
  // The next line that is neither blank nor a comment; throws at the end of the file, saying what was
  // expected.
  Line& next(const std::string& expected) {
    std::string text;
    while (std::getline(in_, text)) {
      ++number_;
      const auto first = text.find_first_not_of(" \t\r");
      if (first == std::string::npos || text[first] == '#') continue;
      line_.number = number_;
      line_.tokens = std::istringstream(text);
      return line_;
    }
    throw Error(path_.string() + ":" + std::to_string(number_) + ": the file ends where " + expected +
                " was expected");
  }
  [[noreturn]] void fail(const std::string& problem) const {
    throw Error(path_.string() + ":" + std::to_string(line_.number) + ": " + problem);
  }

 private:
  std::filesystem::path path_;
  std::istringstream in_;
  int number_ = 0;
  Line line_;
};

// "keyword N" with N in [1, max].
std::size_t readCount(LineReader& reader, const std::string& keyword, std::size_t max) {
  Line& line = reader.next("'" + keyword + " N'");
  std::string word;
  long long count = 0;
  std::string extra;
  if (!(line.tokens >> word >> count) || word != keyword || (line.tokens >> extra) || count < 1 ||
      std::size_t(count) > max)
    reader.fail("expected '" + keyword + " N' with N in [1, " + std::to_string(max) + "]");
  return std::size_t(count);
}

}  // namespace

BezierPatchSet readBezierPatches(const std::filesystem::path& path) {
  LineReader reader(path);
  BezierPatchSet set;
  // Index data is read first and checked against the vertex count afterwards.
  const std::size_t patchCount = readCount(reader, "patches", 1u << 20);
  std::vector<std::array<long long, 16>> indices(patchCount);
  std::vector<int> patchLines(patchCount);
  for (std::size_t p = 0; p < patchCount; ++p) {
    Line& line = reader.next("patch " + std::to_string(p + 1));
    patchLines[p] = line.number;
    std::string extra;
    for (auto& index : indices[p])
      if (!(line.tokens >> index)) reader.fail("a patch needs 16 control-point indices");
    if (line.tokens >> extra) reader.fail("a patch has 16 control-point indices, this line has more");
  }
  const std::size_t vertexCount = readCount(reader, "vertices", 1u << 24);
  for (std::size_t v = 0; v < vertexCount; ++v) {
    Line& line = reader.next("vertex " + std::to_string(v + 1));
    glm::dvec3 p;
    std::string extra;
    if (!(line.tokens >> p.x >> p.y >> p.z) || (line.tokens >> extra))
      reader.fail("expected three numbers 'x y z'");
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      reader.fail("coordinate not finite");
    set.controlPoints.push_back(p);
  }
  for (std::size_t p = 0; p < patchCount; ++p) {
    std::array<std::uint32_t, 16> patch{};
    for (int k = 0; k < 16; ++k) {
      if (indices[p][k] < 1 || std::size_t(indices[p][k]) > vertexCount)
        throw Error(path.string() + ":" + std::to_string(patchLines[p]) + ": index " +
                    std::to_string(indices[p][k]) + " is not in [1, " + std::to_string(vertexCount) + "]");
      patch[k] = std::uint32_t(indices[p][k] - 1);
    }
    set.patches.push_back(patch);
  }
  return set;
}

void zUpToYUp(BezierPatchSet& set) {
  for (auto& p : set.controlPoints) p = glm::dvec3(p.x, p.z, -p.y);
}

PatchPoint evaluateBicubic(const BezierPatchSet& set, std::size_t patch, double u, double v) {
  const auto bu = bernstein(u), bv = bernstein(v), du = bernsteinDerivative(u), dv = bernsteinDerivative(v);
  PatchPoint point{glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const glm::dvec3& p = set.controlPoints[set.patches[patch][4 * r + c]];
      point.position += bu[c] * bv[r] * p;
      point.du += du[c] * bv[r] * p;
      point.dv += bu[c] * dv[r] * p;
    }
  return point;
}

glm::dvec3 patchNormal(const BezierPatchSet& set, std::size_t patch, double u, double v) {
  // Degenerate when |Pu x Pv| is rounding noise against the larger derivative: a collapsed edge has Pu = 0.
  auto normalAt = [&](double su, double sv) -> std::optional<glm::dvec3> {
    const PatchPoint p = evaluateBicubic(set, patch, su, sv);
    const glm::dvec3 n = glm::cross(p.du, p.dv);
    const double scale = std::max(glm::dot(p.du, p.du), glm::dot(p.dv, p.dv));
    if (!(glm::length(n) > 1e-10 * scale)) return std::nullopt;
    return glm::normalize(n);
  };
  if (auto n = normalAt(u, v)) return *n;
  constexpr double kInside = 1e-4;
  if (auto n = normalAt(std::clamp(u, kInside, 1.0 - kInside), std::clamp(v, kInside, 1.0 - kInside)))
    return *n;
  throw Error("Bezier patch " + std::to_string(patch + 1) + " has no normal near (u, v) = (" +
              std::to_string(u) + ", " + std::to_string(v) + ")");
}

TriMesh tessellateBezierPatches(const BezierPatchSet& set, int subdivisions) {
  IBLX_ASSERT(subdivisions >= 1);
  const int n = subdivisions;
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const auto& p : set.controlPoints) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double tolerance = 1e-8 * glm::length(hi - lo);

  // Welding: samples are hashed on a grid of cell size `tolerance`; a sample joins a vertex within
  // `tolerance` in its own or a neighbouring cell whose normal is on the same side (dot > 0). The exception
  // keeps surfaces that merely touch apart: the teapot's handle ends on a corner of the body at an angle of
  // 114°, and one averaged normal there would suit neither.
  struct CellHash {
    std::size_t operator()(const glm::i64vec3& c) const {
      return std::size_t(c.x * 73856093LL ^ c.y * 19349663LL ^ c.z * 83492791LL);
    }
  };
  std::unordered_map<glm::i64vec3, std::vector<std::uint32_t>, CellHash> cells;
  TriMesh mesh;
  std::vector<glm::dvec3> normalSums;
  auto weld = [&](const glm::dvec3& p, const glm::dvec3& normal) -> std::uint32_t {
    const glm::i64vec3 cell(glm::floor(p / tolerance));
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells.find(cell + glm::i64vec3(dx, dy, dz));
          if (it == cells.end()) continue;
          for (const std::uint32_t v : it->second)
            if (glm::length(mesh.positions[v] - p) <= tolerance && glm::dot(normalSums[v], normal) > 0.0) {
              normalSums[v] += normal;
              return v;
            }
        }
    const auto v = std::uint32_t(mesh.positions.size());
    mesh.positions.push_back(p);
    normalSums.push_back(normal);
    cells[cell].push_back(v);
    return v;
  };

  std::vector<std::uint32_t> grid(std::size_t(n + 1) * std::size_t(n + 1));
  for (std::size_t patch = 0; patch < set.patches.size(); ++patch) {
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const double u = double(i) / n, v = double(j) / n;
        grid[std::size_t(j) * (n + 1) + i] =
            weld(evaluateBicubic(set, patch, u, v).position, patchNormal(set, patch, u, v));
      }
    // Cell (i, j) spans u in [i/N, (i+1)/N], v in [j/N, (j+1)/N]; a, b, c, d go counter-clockwise about
    // Pu x Pv (u first, then v).
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::uint32_t a = grid[std::size_t(j) * (n + 1) + i],
                            b = grid[std::size_t(j) * (n + 1) + i + 1],
                            c = grid[std::size_t(j + 1) * (n + 1) + i + 1],
                            d = grid[std::size_t(j + 1) * (n + 1) + i];
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      }
  }
  mesh.normals.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) mesh.normals[v] = glm::normalize(normalSums[v]);
  dropDegenerateTriangles(mesh);
  return mesh;
}

}  // namespace iblx
