// File-name helpers shared by the loaders, writers, the command line and the viewer.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace iblx {

// The extension with its dot, in lower case (".EXR" -> ".exr"), so that formats are chosen
// case-insensitively.
inline std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

}  // namespace iblx
