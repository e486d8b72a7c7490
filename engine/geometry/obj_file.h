// Wavefront OBJ meshes: reading through Debian's tinyobjloader (polygons triangulated) with every problem
// reported as one line naming the file, and writing (for `iblx make-teapot`).
#pragma once

#include "engine/geometry/mesh.h"

#include <filesystem>
#include <string>

namespace iblx {

// Reads the faces of an OBJ file (points, lines, texture coordinates and materials are ignored). The vertex
// normals are the file's when every face vertex has one (`f v//vn`, `f v/vt/vn`), else area-weighted smooth
// normals (computeSmoothNormals). Faces of zero area are dropped with one warning that counts them.
// Throws iblx::Error "FILE[:LINE]: problem" for a missing or unreadable file, a parse error, a non-numeric or
// non-finite coordinate, an index out of range, no faces, or no extent.
TriMesh readObj(const std::filesystem::path& path);

// readObj, then fitToUnitSphere: the mesh of `--object FILE.obj`.
TriMesh loadObjMesh(const std::filesystem::path& path);

// Writes `v`, `vn` (normal i belongs to vertex i) and `f v//vn` lines; each line of `comment` becomes a '#'
// line at the top. Numbers have 7 significant digits. Throws iblx::Error when the file cannot be written.
void writeObj(const std::filesystem::path& path, const TriMesh& mesh, const std::string& comment);

}  // namespace iblx
