#include "node_host.hpp"

namespace loom::detail {

Value Host::fetch_input(int i) {
  const auto& b = s_.inputs[static_cast<std::size_t>(i)];
  if (e_.fed_state(s_, static_cast<std::size_t>(i))) return s_.previous[static_cast<std::size_t>(s_.state_output)];
  if (b.kind == NodeState::Binding::literal) return b.literal_value;
  NodeState& up = e_.at(b.upstream);
  if (!up.done.load(std::memory_order_acquire)) e_.execute({b.upstream});
  if (!up.ok)
    throw UpstreamFailed("input \"" + s_.type->spec.inputs[static_cast<std::size_t>(i)].name + "\": node \"" +
                         up.node->id + "\" " + to_string(up.report.status));
  return up.outputs[static_cast<std::size_t>(b.output)];
}

bool Host::input_set(int i) const {
  return e_.fed_state(s_, static_cast<std::size_t>(i)) ||
         s_.inputs[static_cast<std::size_t>(i)].kind != NodeState::Binding::unset;
}

std::shared_ptr<void> Host::sequence_state(const std::function<std::shared_ptr<void>()>& make) {
  std::lock_guard lock(e_.session.sequence_mutex);
  auto& state = e_.session.sequences[s_.node->id];
  if (!state) state = make();
  return state;
}

void Host::report_progress(double fraction, std::string_view label) {
  if (fraction < last_ + 0.01 && fraction < 1.0 && label == last_label_) return;
  last_ = fraction;
  last_label_ = label;
  if (e_.options.observer) e_.options.observer->node_progress(s_.node->id, fraction, last_label_);
}

void Host::report(bool warning, std::string text) {
  if (warning) {
    std::lock_guard lock(mutex_);
    s_.report.warnings.push_back(text);
  }
  if (e_.options.observer) e_.options.observer->node_message(s_.node->id, warning, text);
}

// The session's scratch store: per node id, the most recently used keys.
std::shared_ptr<void> Host::scratch(std::uint64_t key, const std::function<std::shared_ptr<void>()>& make) {
  auto& session = e_.session;
  {
    std::lock_guard lock(session.scratch_mutex);
    auto& list = session.scratch[s_.node->id];
    for (auto it = list.begin(); it != list.end(); ++it)
      if (it->first == key) {
        auto entry = *it;
        list.erase(it);
        list.push_front(entry);
        return entry.second;
      }
  }
  std::shared_ptr<void> made = make();  // outside the lock: may be slow
  std::lock_guard lock(session.scratch_mutex);
  auto& list = session.scratch[s_.node->id];
  list.emplace_front(key, made);
  if (list.size() > Session::State::kScratchPerNode) list.pop_back();
  return made;
}

}  // namespace loom::detail
