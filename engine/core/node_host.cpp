#include "node_host.hpp"

#include "input_check.hpp"
#include "loom/frame_pattern.hpp"

namespace loom::detail {

Value Host::fetch_input(int i) {
  const auto& b = s_.inputs[static_cast<std::size_t>(i)];
  if (e_.fed_state(s_, static_cast<std::size_t>(i))) return s_.previous[static_cast<std::size_t>(s_.state_output)];
  if (b.kind == NodeState::Binding::literal) return b.literal_value;
  NodeState& up = e_.at(b.upstream);
  if (!up.done.load(std::memory_order_acquire)) e_.execute({b.upstream});
  const InputSpec& spec = s_.type->spec.inputs[static_cast<std::size_t>(i)];
  if (!up.ok)
    throw UpstreamFailed("input \"" + spec.name + "\": node \"" + up.node->id + "\" " +
                         to_string(up.report.status));
  // Every linked value is checked against the input's declaration, as literals
  // are at validation; file paths follow the same rules as literal ones.
  const Value& value = up.outputs[static_cast<std::size_t>(b.output)];
  check_input_value(spec, value);
  if (spec.role == InputRole::value) return value;
  Value path = value;
  if (spec.role == InputRole::output_file)
    path = Value::make<std::string>(expand_frame_pattern(value.as<std::string>(), e_.time.frame));
  path = resolve_path_value(spec, path, e_.graph_dir, e_.options.output_dir, e_.options.allow_outside_output);
  std::lock_guard lock(mutex_);
  return resolved_paths_.emplace_back(std::move(path));
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
  progress_.offer(fraction, label, [&](double f, const std::string& l) {
    if (e_.options.observer) e_.options.observer->node_progress(s_.node->id, f, l);
  });
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
