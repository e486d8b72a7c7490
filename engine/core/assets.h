// Where the project's assets (default environment map, teapot, BRDF files) are found at run time.
#pragma once

#include <filesystem>
#include <string>

namespace iblx {

// `name` in $IBLX_ASSET_DIR when that is set, else in the source tree's assets/ directory.
std::filesystem::path assetPath(const std::string& name);

}  // namespace iblx
