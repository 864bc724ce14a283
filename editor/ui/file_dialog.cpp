#include "file_dialog.hpp"

#include <algorithm>
#include <vector>

#include <imgui.h>
#include <imgui_stdlib.h>

namespace loom::editor {

namespace fs = std::filesystem;

void FileDialog::open(std::string purpose, std::string title, fs::path start, bool saving) {
  purpose_ = std::move(purpose);
  title_ = std::move(title);
  std::error_code ec;
  if (start.empty()) start = fs::current_path(ec);
  if (fs::is_directory(start, ec)) {
    folder_ = start;
    name_.clear();
  } else {
    folder_ = start.parent_path().empty() ? fs::current_path(ec) : start.parent_path();
    name_ = start.filename().string();
  }
  saving_ = saving;
  visible_ = true;
  open_now_ = true;
}

std::optional<fs::path> FileDialog::take(const std::string& purpose) {
  if (!chosen_ || chosen_purpose_ != purpose) return std::nullopt;
  auto path = std::move(chosen_);
  chosen_.reset();
  return path;
}

void FileDialog::draw() {
  if (!visible_) return;
  if (open_now_) {
    ImGui::OpenPopup("file dialog");
    open_now_ = false;
  }
  ImGui::SetNextWindowSize(ImVec2(560, 420), ImGuiCond_Appearing);
  if (!ImGui::BeginPopupModal("file dialog", nullptr)) {
    visible_ = false;
    return;
  }
  ImGui::TextUnformatted(title_.c_str());
  ImGui::TextDisabled("%s", folder_.string().c_str());
  if (ImGui::Button("up")) folder_ = folder_.parent_path();
  std::vector<fs::directory_entry> entries;
  std::error_code ec;
  for (fs::directory_iterator it(folder_, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().rfind('.', 0) != 0) entries.push_back(*it);
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
    if (a.is_directory() != b.is_directory()) return a.is_directory();
    return a.path().filename() < b.path().filename();
  });
  ImGui::BeginChild("entries", ImVec2(0, -ImGui::GetFrameHeightWithSpacing() * 2), true);
  for (const auto& e : entries) {
    const std::string name = e.path().filename().string() + (e.is_directory() ? "/" : "");
    if (ImGui::Selectable(name.c_str(), name == name_, ImGuiSelectableFlags_AllowDoubleClick)) {
      if (e.is_directory()) {
        folder_ = e.path();
      } else {
        name_ = e.path().filename().string();
        if (ImGui::IsMouseDoubleClicked(0)) {
          chosen_ = folder_ / name_;
          chosen_purpose_ = purpose_;
          visible_ = false;
          ImGui::CloseCurrentPopup();
        }
      }
    }
  }
  ImGui::EndChild();
  ImGui::SetNextItemWidth(-120);
  ImGui::InputText("##name", &name_);
  ImGui::SameLine();
  if (ImGui::Button(saving_ ? "Save" : "Open") && !name_.empty()) {
    const fs::path p = fs::path(name_).is_absolute() ? fs::path(name_) : folder_ / name_;
    chosen_ = p;
    chosen_purpose_ = purpose_;
    visible_ = false;
    ImGui::CloseCurrentPopup();
  }
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) {
    visible_ = false;
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

}  // namespace loom::editor
