// The viewer's file browser (file_browser.h).
#include "tools/viewer/file_browser.h"

#include "engine/core/file_names.h"

#include <imgui.h>

#include <algorithm>
#include <cctype>
#include <system_error>

namespace iblx::viewer {

namespace fs = std::filesystem;

void FileBrowser::open(std::string title, std::vector<std::string> extensions, fs::path start) {
  title_ = std::move(title);
  extensions_ = std::move(extensions);
  std::error_code ec;
  if (start.empty() || !fs::is_directory(start, ec))
    start = directory_.empty() ? fs::current_path(ec) : directory_;
  list(start);
  openRequested_ = true;
}

void FileBrowser::list(const fs::path& directory) {
  directories_.clear(), files_.clear(), error_.clear();
  std::error_code ec;
  directory_ = fs::weakly_canonical(directory, ec);
  if (ec) directory_ = directory;
  for (fs::directory_iterator it(directory_, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    const fs::path& path = it->path();
    if (path.filename().string().starts_with('.')) continue;
    if (it->is_directory(ec)) {
      directories_.push_back(path);
      continue;
    }
    const std::string ext = lowerExtension(path);
    if (extensions_.empty() || std::find(extensions_.begin(), extensions_.end(), ext) != extensions_.end())
      files_.push_back(path);
  }
  if (ec) error_ = "cannot list " + directory_.string() + ": " + ec.message();
  std::sort(directories_.begin(), directories_.end());
  std::sort(files_.begin(), files_.end());
}

std::optional<fs::path> FileBrowser::draw() {
  if (openRequested_) ImGui::OpenPopup(title_.c_str()), openRequested_ = false;
  std::optional<fs::path> chosen;
  ImGui::SetNextWindowSize(ImVec2(520.0f, 420.0f), ImGuiCond_Appearing);
  if (!ImGui::BeginPopupModal(title_.c_str())) return chosen;
  ImGui::TextWrapped("%s", directory_.string().c_str());
  if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", error_.c_str());
  ImGui::BeginChild("entries", ImVec2(0.0f, -ImGui::GetFrameHeightWithSpacing()), true);
  std::optional<fs::path> enter;
  if (directory_.has_parent_path() && directory_ != directory_.root_path() && ImGui::Selectable("../"))
    enter = directory_.parent_path();
  for (const fs::path& d : directories_)
    if (ImGui::Selectable((d.filename().string() + "/").c_str())) enter = d;
  for (const fs::path& f : files_)
    if (ImGui::Selectable(f.filename().string().c_str())) chosen = f;
  ImGui::EndChild();
  if (ImGui::Button("cancel")) ImGui::CloseCurrentPopup();
  if (chosen) ImGui::CloseCurrentPopup();
  ImGui::EndPopup();
  if (enter) list(*enter);
  return chosen;
}

}  // namespace iblx::viewer
