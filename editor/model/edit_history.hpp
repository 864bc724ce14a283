// Undo and redo for the editor's graph document, as snapshots of the whole
// graph JSON. A 200-node graph is ~100 KB of JSON, so a snapshot per edit is
// cheaper to get right than an inverse for every kind of edit, and it restores
// exactly what was there (including fields the editor does not understand).
// Consecutive edits with the same merge key (a drag, a slider being held)
// collapse into one step.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace loom::editor {

class EditHistory {
 public:
  explicit EditHistory(std::size_t limit = 500) : limit_(limit) {}

  // Records the document as it was before an edit. Returns false when the edit
  // merges into the previous step (same non-empty merge key, nothing undone
  // in between), in which case nothing is recorded.
  bool record(const nlohmann::json& before, std::string label, const std::string& merge_key);
  // Ends merging: the next edit starts a new step even with the same key.
  void seal() { merge_open_ = false; }
  // Whether the last edit may still merge with the next (a gesture under way).
  bool merging() const { return merge_open_; }

  bool can_undo() const { return !undo_.empty(); }
  bool can_redo() const { return !redo_.empty(); }
  const std::string& undo_label() const;
  const std::string& redo_label() const;

  // Swap `current` with the snapshot of the step undone / redone.
  bool undo(nlohmann::json& current);
  bool redo(nlohmann::json& current);

  void clear();
  // Identifies the state the document is in: equal ids mean equal documents.
  std::uint64_t state() const { return state_; }

 private:
  struct Step {
    nlohmann::json document;
    std::string label;
    std::uint64_t state;  // the id of the state `document` is
  };
  std::size_t limit_;
  std::vector<Step> undo_, redo_;
  std::string merge_key_;
  bool merge_open_ = false;
  std::uint64_t state_ = 0, next_state_ = 1;
};

}  // namespace loom::editor
