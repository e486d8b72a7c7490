// `iblx make-teapot`: tessellates Newell's Bezier patches (assets/teapot_patches.txt) into the OBJ that ships
// as assets/teapot.obj and that `--object teapot` loads.
#include "engine/core/assets.h"
#include "engine/core/error.h"
#include "engine/geometry/bezier_patches.h"
#include "engine/geometry/obj_file.h"
#include "tools/cli/cli_options.h"
#include "tools/cli/commands.h"

#include <cstdio>

namespace iblx::cli {

int cmdMakeTeapot(const Args& args) {
  int subdivisions = 12;
  std::filesystem::path patches = assetPath("teapot_patches.txt");
  std::filesystem::path out = "teapot.obj";
  ArgParser parser("make-teapot");
  parser.value("--subdivisions", "N", "grid cells per patch side, 1-64 (default 12: 9120 triangles)",
               [&](const std::string& v) { subdivisions = int(parseUint("--subdivisions", v, 1, 64)); });
  parser.value("--patches", "FILE", "Bezier patch file (default assets/teapot_patches.txt)",
               [&](const std::string& v) { patches = v; });
  parser.value("--out", "FILE", "output .obj (default teapot.obj)", [&](const std::string& v) { out = v; });
  if (parser.parseOrShowHelp(args)) return 0;
  if (out.extension() != ".obj") throw Error("--out " + out.string() + ": must end in .obj");
  if (const auto parent = out.parent_path(); !parent.empty() && !std::filesystem::is_directory(parent))
    throw Error("--out " + out.string() + ": directory '" + parent.string() + "' does not exist");

  BezierPatchSet set = readBezierPatches(patches);
  zUpToYUp(set);
  const TriMesh mesh = tessellateBezierPatches(set, subdivisions);
  const std::string comment =
      "The Utah teapot: Martin Newell's 32 bicubic Bezier patches (University of Utah, 1975), +Y up.\n"
      "Made by `iblx make-teapot --subdivisions " +
      std::to_string(subdivisions) + "` from " + patches.filename().string() + ": " +
      std::to_string(mesh.positions.size()) + " vertices, " + std::to_string(mesh.triangles.size()) +
      " triangles, normals from the patches' derivatives.";
  writeObj(out, mesh, comment);
  std::printf("wrote %s (%zu patches, %zu vertices, %zu triangles)\n", out.string().c_str(),
              set.patches.size(), mesh.positions.size(), mesh.triangles.size());
  return 0;
}

}  // namespace iblx::cli
