// The on-disk cache location (engine/core/cache_dir.h).
#include "engine/core/cache_dir.h"

#include <cstdio>
#include <cstdlib>

namespace iblx {

std::filesystem::path defaultCacheDir() {
  if (const char* dir = std::getenv("IBLX_CACHE_DIR")) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::filesystem::path(xdg) / "iblx";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "iblx";
  return {};
}

std::string hexKey(std::uint64_t key) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(key));
  return buffer;
}

}  // namespace iblx
