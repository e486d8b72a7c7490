// report.html of `converge` and `hardcases`: one self-contained page (images embedded as data URIs, a few
// lines of script for sorting tables) that a browser opens from disk with no server and no download.
#pragma once

#include "engine/analysis/convergence.h"

#include <filesystem>
#include <string>
#include <vector>

namespace iblx::cli {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void heading(const std::string& text, int level = 2);
  void paragraph(const std::string& text);
  // Clicking a header sorts the rows by that column (numerically where the cells start with a number).
  void table(const TextTable& table);
  // A wrapping row of captioned PNG files (read from disk when the page is written), drawn displayWidth
  // pixels wide (0: their own size); small images are scaled up without smoothing, so pixels stay pixels.
  struct Figure {
    std::string caption;
    std::filesystem::path png;
  };
  void figures(const std::vector<Figure>& figures, int displayWidth);

  // Writes the page atomically; throws Error naming a figure that cannot be read.
  void write(const std::filesystem::path& path) const;

 private:
  std::string title_;
  std::vector<std::string> blocks_;  // HTML, with one placeholder per figure
  std::vector<std::filesystem::path> images_;
};

// RFC 4648 base64, for data URIs.
std::string base64(const std::vector<unsigned char>& bytes);
// Text for HTML element content and attribute values.
std::string htmlEscape(const std::string& text);

}  // namespace iblx::cli
