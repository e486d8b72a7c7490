// A small file browser for the viewer (Dear ImGui has none): a popup that lists one directory, filtered by
// extension, and returns the file picked. Directories are entered by clicking them; ".." goes up.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace iblx::viewer {

class FileBrowser {
 public:
  // extensions: lower case with the dot, e.g. {".exr", ".hdr"}; empty shows every file.
  void open(std::string title, std::vector<std::string> extensions, std::filesystem::path start = {});
  // Draws the popup if it is open; returns the chosen file once.
  std::optional<std::filesystem::path> draw();

 private:
  void list(const std::filesystem::path& directory);

  std::string title_;
  std::vector<std::string> extensions_;
  std::filesystem::path directory_;
  std::vector<std::filesystem::path> directories_, files_;
  std::string error_;
  bool openRequested_ = false;
};

}  // namespace iblx::viewer
