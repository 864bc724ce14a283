#include "edit_history.hpp"

namespace loom::editor {

bool EditHistory::record(const nlohmann::json& before, std::string label, const std::string& merge_key) {
  if (merge_open_ && !merge_key.empty() && merge_key == merge_key_ && !undo_.empty()) {
    state_ = next_state_++;
    return false;
  }
  undo_.push_back({before, std::move(label), state_});
  if (undo_.size() > limit_) undo_.erase(undo_.begin());
  redo_.clear();
  merge_key_ = merge_key;
  merge_open_ = !merge_key.empty();
  state_ = next_state_++;
  return true;
}

const std::string& EditHistory::undo_label() const {
  static const std::string none;
  return undo_.empty() ? none : undo_.back().label;
}

const std::string& EditHistory::redo_label() const {
  static const std::string none;
  return redo_.empty() ? none : redo_.back().label;
}

bool EditHistory::undo(nlohmann::json& current) {
  if (undo_.empty()) return false;
  Step step = std::move(undo_.back());
  undo_.pop_back();
  redo_.push_back({std::move(current), step.label, state_});
  current = std::move(step.document);
  state_ = step.state;
  merge_open_ = false;
  return true;
}

bool EditHistory::redo(nlohmann::json& current) {
  if (redo_.empty()) return false;
  Step step = std::move(redo_.back());
  redo_.pop_back();
  undo_.push_back({std::move(current), step.label, state_});
  current = std::move(step.document);
  state_ = step.state;
  merge_open_ = false;
  return true;
}

void EditHistory::clear() {
  undo_.clear();
  redo_.clear();
  merge_open_ = false;
  state_ = next_state_++;
}

}  // namespace loom::editor
