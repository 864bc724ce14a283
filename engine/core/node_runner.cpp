// Running one node, in four steps:
//   1. settle without running: cancelled, served from a cache, or unable to
//      run (a simulation's previous state or a non-lazy input failed);
//   2. invoke: bind the linked inputs, call the body, check its outputs, and
//      turn whatever it threw into an outcome;
//   3. record the outcome in the node's report, and keep a result that ran;
//   4. finish: mark the node done and tell the observer.
#include <new>
#include <stdexcept>

#include <tbb/task_arena.h>

#include "evaluation.hpp"
#include "node_host.hpp"

namespace loom::detail {

std::string upstream_failure(const InputSpec& input, const NodeState& upstream) {
  return "input \"" + input.name + "\": node \"" + upstream.node->id + "\" " + to_string(upstream.report.status);
}

namespace {

// What a node body threw, as the node's status and message.
Evaluation::Outcome failure(std::exception_ptr thrown) {
  Evaluation::Outcome o;
  o.status = NodeStatus::failed;
  try {
    std::rethrow_exception(thrown);
  } catch (const UpstreamFailed& e) {
    o.status = NodeStatus::skipped;
    o.error = e.what();
  } catch (const std::bad_alloc&) {
    o.error = "out of memory: the inputs ask for more memory than this machine can give";
  } catch (const std::length_error& e) {
    o.error = std::string("the inputs ask for a size beyond what memory can hold (") + e.what() + ")";
  } catch (const std::exception& e) {
    o.error = e.what();
  } catch (...) {
    o.error = "unknown exception";
  }
  return o;
}

// Every output set, and none holding NaN, infinity or a broken index: the
// type's check (TypeTraits::check) names what is wrong, the engine the output.
void check_outputs(const NodeSpec& spec, const std::vector<Value>& values) {
  for (std::size_t o = 0; o < spec.outputs.size(); ++o) {
    if (!values[o])
      throw Error("node did not set its output \"" + spec.outputs[o].name + "\" (a bug in " + spec.name + ")");
    try {
      values[o].check();
    } catch (const Error& e) {
      throw Error("output \"" + spec.outputs[o].name + "\": " + e.what());
    }
  }
}

}  // namespace

// An image split over processes: this one's part is replaced by the whole,
// gathered from every part, and the node's summaries are recomputed from it.
// A split that deals parts as processes ask for them (an MPI run with
// --mpi-deal dynamic) may instead hand this process another part in
// combine(): region() then names it, and the body runs again on it.
void Evaluation::gather_parts(NodeState& s, Outputs& out, const std::function<void()>& run_again) {
  const NodeSpec& spec = s.type->spec;
  const PixelSplit& split = *options.pixel_split;
  PixelRegion ran = split.region(s.node->id);
  if (ran.whole() || ran.by_samples) return;  // by samples, every part holds the whole already
  for (;;) {
    split.combine(s.node->id, spec, out.values());
    const PixelRegion next = split.region(s.node->id);
    if (next.part == ran.part && next.parts == ran.parts) break;
    run_again();
    ran = next;
  }
  if (spec.summarize) spec.summarize(out);
}

void Evaluation::run_node(NodeIndex n) {
  NodeState& s = at(n);
  if (!settled_without_running(n)) record(s, invoke(s));
  finish(s);
}

bool Evaluation::settled_without_running(NodeIndex n) {
  NodeState& s = at(n);
  if (cancelled()) {
    s.report.status = NodeStatus::skipped;
    s.report.error = "cancelled";
    return true;
  }
  if (s.cacheable && take_cached(s)) return true;
  if (s.type->spec.simulation() && time.frame > time.start && !step_to_previous(n)) return true;
  return !ensure_inputs(s);
}

bool Evaluation::take_cached(NodeState& s) {
  auto found = cache_find(s, s.hash);
  if (!found) return false;
  s.outputs = std::move(found->outputs);
  s.files = std::move(found->files);
  s.ok = true;
  s.report.status = NodeStatus::cached;
  s.report.compute_seconds += found->seconds;
  (found->from_disk ? s.report.disk_hits : s.report.memory_hits) += 1;
  return true;
}

// Normally the scheduler has run every non-lazy input already; if not (a lazy
// fetch or a corrupt disk entry reached this node), runs them now. False, with
// the report saying which, when one of them did not succeed.
bool Evaluation::ensure_inputs(NodeState& s) {
  const auto& specs = s.type->spec.inputs;
  std::vector<NodeIndex> missing;
  for (std::size_t i = 0; i < s.inputs.size(); ++i)
    if (links_upstream(s, i) && !specs[i].lazy && !at(s.inputs[i].upstream).done.load(std::memory_order_acquire))
      missing.push_back(s.inputs[i].upstream);
  if (!missing.empty()) execute(missing);
  for (std::size_t i = 0; i < s.inputs.size(); ++i) {
    if (!links_upstream(s, i) || specs[i].lazy) continue;
    const NodeState& up = at(s.inputs[i].upstream);
    if (!up.ok) {
      s.report.status = NodeStatus::skipped;
      s.report.error = upstream_failure(specs[i], up);
      return false;
    }
  }
  return true;
}

Evaluation::Outcome Evaluation::invoke(NodeState& s) {
  const NodeSpec& spec = s.type->spec;
  if (options.observer) options.observer->node_started(s.node->id, spec.name);
  Host host(*this, s);
  Inputs in(spec, host);
  Outputs out(spec);
  FrameTime t = time;
  t.step = spec.simulation() && time.frame > time.start ? 1.0 / time.fps : 0.0;
  Context ctx(host, s.node->id, s.seed, graph_dir, options.output_dir, t);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  Outcome o;
  auto run_body = [&] {
    const double before = elapsed();
    tbb::this_task_arena::isolate([&] {
      if (s.node->repeat) run_repeat(*this, s, in, out, ctx);
      else s.type->run(in, out, ctx);
    });
    o.seconds += elapsed() - before;  // the body's time, not the output checks' nor the gather's
    check_outputs(spec, out.values());
  };
  try {
    // Every non-lazy linked value is bound before the body runs, whether or
    // not the body reads it (the binding checks ranges, choices and paths).
    for (std::size_t i = 0; i < s.inputs.size(); ++i)
      if (links_upstream(s, i) && !spec.inputs[i].lazy) host.fetch_input(static_cast<int>(i));
    run_body();
    if (options.pixel_split && spec.pixel_independent) gather_parts(s, out, run_body);
    o.outputs = std::move(out.values());
    o.status = NodeStatus::ran;
  } catch (...) {
    o = failure(std::current_exception());
    o.seconds = elapsed();
  }
  return o;
}

void Evaluation::record(NodeState& s, Outcome outcome) {
  s.previous.clear();  // the step is done with it: a state copied once per frame, not held twice
  s.report.status = outcome.status;
  s.report.error = std::move(outcome.error);
  s.report.seconds += outcome.seconds;
  s.report.runs += 1;
  if (outcome.status != NodeStatus::ran) return;
  s.report.compute_seconds += outcome.seconds;
  s.outputs = std::move(outcome.outputs);
  s.ok = true;
  if (s.cacheable && !cancelled()) cache_put(s, outcome.seconds);
}

}  // namespace loom::detail
