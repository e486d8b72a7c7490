// Asset lookup (engine/core/assets.h).
#include "engine/core/assets.h"

#include <cstdlib>

namespace iblx {

std::filesystem::path assetPath(const std::string& name) {
  if (const char* dir = std::getenv("IBLX_ASSET_DIR")) return std::filesystem::path(dir) / name;
  return std::filesystem::path(IBLX_SOURCE_DIR) / "assets" / name;
}

}  // namespace iblx
