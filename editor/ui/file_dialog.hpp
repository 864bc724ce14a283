// A plain ImGui file dialog (no extra dependency): a folder listing, a path
// field, and OK/Cancel. One dialog at a time; the caller asks each frame
// whether it finished and for which purpose.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace loom::editor {

class FileDialog {
 public:
  // `purpose` identifies the request ("open", "save", "input:node.path").
  void open(std::string purpose, std::string title, std::filesystem::path start, bool saving);
  void draw();
  // The chosen path once, when the dialog for `purpose` was confirmed.
  std::optional<std::filesystem::path> take(const std::string& purpose);
  bool active() const { return visible_; }

 private:
  std::string purpose_, title_;
  std::filesystem::path folder_;
  std::string name_;
  bool saving_ = false, visible_ = false, open_now_ = false;
  std::optional<std::filesystem::path> chosen_;
  std::string chosen_purpose_;
};

}  // namespace loom::editor
