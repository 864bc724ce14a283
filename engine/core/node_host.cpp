#include "node_host.hpp"

#include "loom/graph.hpp"

namespace loom::detail {

namespace {

// Lazy fetches nested on this thread's stack (see kMaxLazyChain).
thread_local int lazy_depth = 0;

}  // namespace

Value Host::fetch_input(int i) {
  const auto& b = s_.inputs[static_cast<std::size_t>(i)];
  if (e_.takes_previous_state(s_, static_cast<std::size_t>(i)))
    return s_.previous[static_cast<std::size_t>(s_.state_output)];
  if (b.kind == NodeState::Binding::literal) return b.literal_value;
  const InputSpec& spec = s_.type->spec.inputs[static_cast<std::size_t>(i)];
  NodeState& up = e_.at(b.upstream);
  if (!up.done.load(std::memory_order_acquire)) {
    if (lazy_depth >= kMaxLazyChain)
      throw Error("input \"" + spec.name + "\": more than " + std::to_string(kMaxLazyChain) +
                  " lazy inputs are nested in one another (a chain of Switch nodes?): split the chain");
    struct Nested {  // one level deeper while the upstream runs, however it ends
      Nested() { ++lazy_depth; }
      ~Nested() { --lazy_depth; }
    } nested;
    e_.execute({b.upstream});
  }
  if (!up.ok) throw UpstreamFailed(upstream_failure(spec, up));
  s_.add_files(up.files);
  Value bound = bind_value(spec, up.outputs[static_cast<std::size_t>(b.output)], e_.place);
  e_.check_interface_inputs(s_, i, bound);
  if (spec.role == InputRole::value) return bound;
  // A linked path's file is not in the hash (the path was not known when
  // hashing): the result keeps the file's stamp instead.
  if (spec.role == InputRole::input_file) s_.add_files({stamp_of(bound.as<std::string>())});
  std::lock_guard lock(mutex_);
  return resolved_paths_.emplace_back(std::move(bound));  // in.get returns a reference into it
}

void Host::depends_on_file(const std::filesystem::path& path) {
  s_.add_files({stamp_of(std::filesystem::absolute(path).lexically_normal().string())});
}

PixelRegion Host::pixel_region() const {
  const PixelSplit* split = e_.options.pixel_split;
  return split && s_.type->spec.pixel_independent ? split->region(s_.node->id) : PixelRegion{};
}

void Host::sum_over_parts(double* values, std::size_t count, double work) {
  if (pixel_region().by_samples) e_.options.pixel_split->sum(values, count, work);
}

int Host::take_slot() { return pixel_region().dealt() ? e_.options.pixel_split->take_slot() : -1; }

// Partials go to the observer and nowhere else: never into s_.outputs, the
// cache or a downstream input, so a run with listeners ends bit-identical to
// one without.
bool Host::partial_wanted() const {
  return e_.options.observer && e_.options.observer->wants_partial(s_.node->id);
}

void Host::publish_partial(std::string_view output, Value value, const PartialInfo& info) {
  const NodeSpec& spec = s_.type->spec;
  const int o = spec.output_index(output);
  if (o < 0) throw Error("publish_partial: no output \"" + std::string(output) + "\"");
  if (value.type() != spec.outputs[static_cast<std::size_t>(o)].type)
    throw Error("publish_partial: output \"" + std::string(output) + "\" is a " +
                spec.outputs[static_cast<std::size_t>(o)].type->name);
  e_.options.observer->node_partial(s_.node->id, std::string(output), value, info);
}

bool Host::input_set(int i) const {
  return e_.takes_previous_state(s_, static_cast<std::size_t>(i)) ||
         s_.inputs[static_cast<std::size_t>(i)].kind != NodeState::Binding::unset;
}

std::shared_ptr<void> Host::sequence_state(const std::function<std::shared_ptr<void>()>& make) {
  std::lock_guard lock(e_.session.sequence_mutex);
  auto& state = e_.session.sequences[e_.scoped_id(s_)];
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

// The session's scratch store: per node (scoped id), the most recently used keys.
std::shared_ptr<void> Host::scratch(std::uint64_t key, const std::function<std::shared_ptr<void>()>& make) {
  auto& session = e_.session;
  {
    std::lock_guard lock(session.scratch_mutex);
    auto& list = session.scratch[e_.scoped_id(s_)];
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
  auto& list = session.scratch[e_.scoped_id(s_)];
  list.emplace_front(key, made);
  if (list.size() > Session::State::kScratchPerNode) list.pop_back();
  return made;
}

}  // namespace loom::detail
