// Simulation stepping: a step node past the start frame gets its own output
// at the previous frame, found in the caches or computed by evaluating the
// graph at each missing frame in order (see docs/architecture.md).
#include "computation_hash.hpp"
#include "evaluation.hpp"
#include "node_host.hpp"

namespace loom::detail {

bool Evaluation::step_to_previous(NodeIndex n) {
  NodeState& s = at(n);
  if (stepping_node == n) {
    s.previous = stepping_previous;
    return true;
  }
  const int want = time.frame - 1;
  if (auto found = cache_find(s, state_hash(s.chain, want))) {
    s.previous = std::move(found->outputs);
    s.add_files(found->files);
    return true;
  }
  // The latest frame before `want` that is kept, then step on from there,
  // evaluating the graph at each frame so time-dependent inputs are current.
  int next = time.start;
  std::vector<Value> previous;
  for (int k = want - 1; k >= time.start; --k)
    if (auto found = cache_find(s, state_hash(s.chain, k))) {
      previous = std::move(found->outputs);
      s.add_files(found->files);
      next = k + 1;
      break;
    }
  for (int g = next; g <= want; ++g) {
    if (cancelled()) {
      s.report.status = NodeStatus::skipped;
      s.report.error = "cancelled";
      return false;
    }
    Host(*this, s).report_progress(static_cast<double>(g - next) / (time.frame - next),
                                   "stepping frame " + std::to_string(g) + " of " + std::to_string(time.frame));
    FrameTime t = time;
    t.frame = g;
    Evaluation sub(session, graph, options, t);
    sub.stepping_node = n;
    sub.stepping_previous = std::move(previous);
    sub.build();
    sub.execute({n});
    NodeState& step = sub.at(n);
    s.report.runs += step.report.runs;
    s.report.seconds += step.report.seconds;
    s.report.compute_seconds += step.report.compute_seconds;
    if (!step.ok) {
      s.report.status = step.report.status == NodeStatus::failed ? NodeStatus::failed : NodeStatus::skipped;
      s.report.error = "at frame " + std::to_string(g) + ": " + step.report.error;
      return false;
    }
    previous = step.outputs;
    s.add_files(step.files);
  }
  s.previous = std::move(previous);
  return true;
}

}  // namespace loom::detail
