// `loom run` over MPI ranks: what each rank evaluates (mpi_run.hpp).
//
// Frames (several frames, or --mpi-split frames): rank r evaluates the r-th
// of `size` contiguous blocks of the range, or with --mpi-deal dynamic the
// runs of frames a Dealer hands it as it asks (for_my_frames). The stages are the engine's
// (GraphView::stages): the simulations the targets read are stepped first, in
// order, by rank 0, every state stored in the persistent cache; the ranks then
// read each state of their frames from it (docs/architecture.md, "One run over
// MPI ranks": "Simulations: one rank steps"). Sequence sinks (SaveVideo) run
// on rank 0 after every rank's frames, reading the frames back from the same cache.
//
// Tiles (one frame; with --mpi-split samples, nodes that declare sample
// passes are split by samples instead): every pixel-independent node the targets need is
// split alone, in dependency order: every rank computes its interleaved tiles
// and they are gathered, in place, on rank 0, or on every rank when a node
// split later reads them (gathers(), MpiWorld::split). Each of these
// evaluations also targets the nodes split before it, so that the memory
// cache keeps them all; rank 0 then evaluates the targets, finding them there.
#include "mpi/mpi_run.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <iostream>
#include <limits>
#include <optional>
#include <set>

#include "loom/disk_cache.hpp"
#include "loom/error.hpp"
#include "loom/graph_view.hpp"
#include "mpi/mpi_settings.hpp"
#include "mpi/mpi_world.hpp"

namespace loom::runner {
namespace {

// The run's targets as addresses: --target's, or empty for every sink.
std::vector<std::string> target_texts(const EvalOptions& options) {
  std::vector<std::string> texts;
  for (const Target& t : options.targets) texts.push_back(t.output.empty() ? t.node : link_text(t.node, t.output));
  return texts;
}

std::vector<Target> as_targets(const std::vector<std::string>& texts) {
  std::vector<Target> targets;
  for (const auto& t : texts) targets.push_back(parse_target(t));
  return targets;
}

// failed, then skipped, then ran, then cached, then pruned (NodeReport's order).
int precedence(NodeStatus s) {
  switch (s) {
    case NodeStatus::failed: return 4;
    case NodeStatus::skipped: return 3;
    case NodeStatus::ran: return 2;
    case NodeStatus::cached: return 1;
    case NodeStatus::pruned: return 0;
  }
  return 0;
}

// `part`'s reports added to `into` (runs and hits summed, the status by
// precedence), and its outputs when they are what the run asked for.
void merge(EvalResult& into, const EvalResult& part, bool outputs = true) {
  for (const auto& [id, r] : part.nodes) {
    NodeReport& n = into.nodes[id];
    n.seconds += r.seconds;
    n.compute_seconds += r.compute_seconds;
    n.runs += r.runs;
    n.memory_hits += r.memory_hits;
    n.disk_hits += r.disk_hits;
    n.warnings.insert(n.warnings.end(), r.warnings.begin(), r.warnings.end());
    if (precedence(r.status) > precedence(n.status)) {
      n.status = r.status;
      n.error = r.error;
    }
  }
  if (outputs)
    for (const auto& [target, values] : part.outputs) into.outputs.emplace(target, values);
  into.frames = std::max(into.frames, part.frames);
  into.cancelled = into.cancelled || part.cancelled;
}

// The run's own cache in --out (no --cache given), while it exists: removed
// also when a rank ends every rank, so that no .loom-mpi-cache stays behind.
std::optional<std::filesystem::path> g_own_store;

void remove_own_store() {
  if (!g_own_store) return;
  std::error_code ec;
  std::filesystem::remove_all(*g_own_store, ec);
}

// A rank whose part failed or was cancelled ends every rank: the others may
// be waiting for its tiles or its frames.
void end_every_rank_unless_ok(MpiWorld& world, const Graph& graph, const EvalResult& r) {
  if (!r.ok() || r.cancelled) remove_own_store();
  if (r.cancelled) {
    std::cerr << "rank " << world.rank() << ": interrupted: ending every rank\n";
    world.abort(kInterrupted);
  }
  if (r.ok()) return;
  for (const auto& [id, n] : r.nodes)
    if (n.status == NodeStatus::failed)
      std::cerr << "error: rank " << world.rank() << ": node \"" << id << "\" (" << graph.nodes.at(id).type
                << ") failed: " << n.error << "\n";
  std::cerr << "rank " << world.rank() << ": a node failed: ending every rank\n";
  world.abort(kNodeFailed);
}

// The persistent cache with every result stored, however cheap: how states
// reach the ranks that render them and frames the sequence sinks on rank 0.
// Without --cache, a folder of the run's own in the (shared) output folder.
DiskCache::Options storing_everything(const EvalOptions& options) {
  DiskCache::Options o;
  if (options.disk_cache) o = options.disk_cache->options();
  else o.dir = options.output_dir / ".loom-mpi-cache";
  o.min_seconds = 0;
  o.read_entry_seconds = 0;
  o.read_mb_per_s = 1e300;
  o.max_sequence_share = 1;  // up to --cache-limit; frames beyond it are computed again on rank 0
  return o;
}

// How evenly the ranks shared some work (a split node's tiles or sample
// passes, frames, sweep points): each rank's time in it (a split node's
// gather excluded), the slowest over the mean.
void report_balance(const MpiWorld& world, const std::string& what, const std::vector<double>& seconds) {
  if (world.rank() != 0) return;
  double sum = 0, slowest = 0;
  for (double s : seconds) {
    sum += s;
    slowest = std::max(slowest, s);
  }
  const double mean = sum / double(seconds.size());
  std::string each;
  for (double s : seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%s%.3f", each.empty() ? "" : " ", s);
    each += text;
  }
  std::fprintf(stderr,
               "mpi: %s computed in %.3f s on the slowest of %zu ranks, %.3f s on average "
               "(imbalance %.3f; ranks 0..%zu: %s s)\n",
               what.c_str(), slowest, seconds.size(), mean, mean > 0 ? slowest / mean : 1.0, seconds.size() - 1,
               each.c_str());
}

// `evaluate` run on a thread of its own while this one lets MPI answer the
// other ranks' asks for work (Dealer::answer, every millisecond): over TCP
// a rank asking would otherwise wait until rank 0 next enters MPI, after its
// frame. Nothing in a frame's evaluation calls MPI (its nodes are not split).
EvalResult evaluate_answering(Dealer& dealer, const std::function<EvalResult()>& evaluate) {
  std::future<EvalResult> result = std::async(std::launch::async, evaluate);
  while (result.wait_for(std::chrono::milliseconds(1)) != std::future_status::ready) dealer.answer();
  return result.get();
}

// Calls `evaluate` on this rank's frames of `range`: the r-th of `size`
// contiguous blocks, or, with --mpi-deal dynamic, a part at a time (a frame,
// or a run of them: Dealer) as the rank asks for the next (a slower rank
// takes fewer; rank 0 answers the asks while it evaluates, the Dealer it is given).
// Rank 0 then prints each rank's time in its frames (report_balance) and,
// dealt, how many each took.
void for_my_frames(MpiWorld& world, FrameRange range, const std::function<void(FrameRange, Dealer*)>& evaluate) {
  const auto start = std::chrono::steady_clock::now();
  const long frames = long(range.last) - range.first + 1;
  std::unique_ptr<Dealer> dealer;
  if (mpi_settings().deal != "dynamic") {
    const int first = range.first + int(frames * world.rank() / world.size());
    const int last = range.first + int(frames * (world.rank() + 1) / world.size()) - 1;
    if (first <= last) evaluate({first, last}, nullptr);
  } else {
    dealer = world.dealer(frames);
    for (Dealer::Part p; !(p = dealer->next()).empty();)
      evaluate({range.first + int(p.begin), range.first + int(p.end) - 1}, world.rank() == 0 ? dealer.get() : nullptr);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (dealer) dealer->report(std::to_string(frames) + " frames");
  report_balance(world, "frames", world.gather_all(seconds));
}

EvalResult evaluate_frames(MpiWorld& world, Session& session, const GraphView& view, const EvalOptions& options,
                           FrameRange range) {
  const Graph& graph = view.graph();
  const RunStages stages = view.stages(target_texts(options));
  const std::vector<Target> work = as_targets(stages.per_frame), sequence = as_targets(stages.sequences),
                            simulations = as_targets(stages.simulations);

  // Targets over several frames print every frame's value, as one process
  // does: rank 0 reads them back from the store after every rank's frames.
  const bool targets_over_frames = !options.targets.empty() && range.last > range.first;
  std::optional<DiskCache> store;
  if (!sequence.empty() || !simulations.empty() || targets_over_frames) {
    if (!options.disk_cache) {
      g_own_store = storing_everything(options).dir;
      if (world.rank() == 0) remove_own_store();  // a killed run's leftovers
      world.barrier();
    }
    store.emplace(storing_everything(options));
  }
  EvalResult result;
  auto evaluate = [&](std::vector<Target> targets, FrameRange frames, Dealer* answering = nullptr) {
    EvalOptions o = options;
    o.targets = std::move(targets);
    o.frames = frames;
    if (store) o.disk_cache = &*store;
    const EvalResult r = answering ? evaluate_answering(*answering, [&] { return session.evaluate(graph, o); })
                                   : session.evaluate(graph, o);
    end_every_rank_unless_ok(world, graph, r);
    merge(result, r, !options.targets.empty());  // what the run asked for, as one process prints it
  };
  if (!simulations.empty()) {
    if (world.rank() == 0) evaluate(simulations, range);
    world.barrier();
  }
  if (!work.empty()) {
    for_my_frames(world, range, [&](FrameRange frames, Dealer* answering) { evaluate(work, frames, answering); });
  }
  world.barrier();
  if (world.rank() == 0 && !sequence.empty()) evaluate(sequence, range);
  if (world.rank() == 0 && targets_over_frames) {
    EvalOptions o = options;
    o.frames = range;
    o.disk_cache = &*store;
    const EvalResult r = session.evaluate(graph, o);  // every frame's values, read back in order
    end_every_rank_unless_ok(world, graph, r);
    result.outputs = r.outputs;  // its reports are not merged: nothing ran twice
    result.outputs_per_frame = r.outputs_per_frame;
  }
  if (world.rank() == 0 && store && options.disk_cache) store->trim();
  if (world.rank() == 0 && store && !options.disk_cache) {
    remove_own_store();
    g_own_store.reset();
  }
  return result;
}

// Where a split node's images are gathered: on every rank when a node split
// after it reads them (every rank evaluates that node, upstream included),
// else on rank 0 alone, which runs the targets. Its own tiles would not do
// for a split node downstream: pixel-independent says an output pixel
// depends on the inputs and its position, not that it reads the inputs at
// that position alone (a lens distortion, a texture lookup).
std::vector<Gather> gathers(const GraphView& view, const std::vector<std::string>& split) {
  std::vector<Gather> g(split.size(), Gather::to_rank_0);
  for (std::size_t later = 1; later < split.size(); ++later)
    for (const std::string& id : view.upstream({split[later]}))
      for (std::size_t i = 0; i < later; ++i)
        if (split[i] == id) g[i] = Gather::to_every_rank;
  return g;
}

EvalResult evaluate_tiles(MpiWorld& world, Session& session, const GraphView& view, const EvalOptions& options,
                          FrameRange range) {
  const Graph& graph = view.graph();
  std::vector<std::string> split;
  for (const auto& id : view.upstream(target_texts(options)))
    if (view.type(id).spec.pixel_independent) split.push_back(id);
  const std::vector<Gather> gather = gathers(view, split);
  EvalResult parts;
  std::vector<Target> split_so_far;  // targets of each evaluation, so the memory cache keeps them all
  for (std::size_t i = 0; i < split.size(); ++i) {
    const std::string& id = split[i];
    const NodeSpec& spec = view.type(id).spec;
    split_so_far.push_back({id, ""});
    const int kept = session.cached_frames(graph, id, range, options).empty() ? 0 : 1;
    if (world.min_over_ranks(kept) == 1) continue;
    EvalOptions o = options;
    o.targets = split_so_far;
    const bool by_samples = mpi_settings().split == "samples" && spec.sample_passes;
    const bool dealt = mpi_settings().deal == "dynamic";
    const auto pixel_split = world.split(id, mpi_settings().tile, by_samples, gather[i], dealt);
    o.pixel_split = pixel_split.get();
    // A rank left with its part reads the cache but stores nothing: its part is not the result.
    std::optional<DiskCache> reading_only;
    if (o.disk_cache && gather[i] == Gather::to_rank_0 && world.rank() != 0 && !by_samples) {
      DiskCache::Options never_storing = o.disk_cache->options();
      never_storing.min_seconds = std::numeric_limits<double>::infinity();
      o.disk_cache = &reading_only.emplace(never_storing);
    }
    // A rank that found the result would not compute its tiles while the others wait for them.
    if (world.max_over_ranks(kept) == 1) o.disk_cache = nullptr;
    const EvalResult r = session.evaluate(graph, o);
    pixel_split->report();  // first: it ends rank 0's answering thread, before any other MPI call
    end_every_rank_unless_ok(world, graph, r);
    const std::string what = id + (by_samples ? ": sample passes" : ": tiles");
    report_balance(world, what, world.gather_all(r.nodes.at(id).seconds));
    merge(parts, r, false);
  }
  if (split_so_far.empty() && world.rank() == 0)
    std::fprintf(stderr, "mpi: one frame and no pixel-independent node: rank 0 runs the graph, %d ranks wait\n",
                 world.size() - 1);
  if (world.rank() != 0) return parts;
  EvalResult whole = session.evaluate(graph, options);
  merge(whole, parts, false);
  return whole;
}

// Every rank must write into one output folder (on a shared filesystem):
// frames, simulation states and the run's own cache pass through it. Rank 0
// leaves a marker there; a rank that cannot see it has a folder of its own
// (each rank given its own --out ran with exit 0 and no word).
void require_shared_output(MpiWorld& world, const std::filesystem::path& out) {
  const std::filesystem::path marker = out / ".loom-mpi-shared";
  std::error_code ec;
  if (world.rank() == 0) {
    std::filesystem::create_directories(out, ec);
    std::ofstream(marker) << "every rank of an MPI run must see this file\n";
  }
  world.barrier();
  const int seen = std::filesystem::exists(marker, ec) ? 1 : 0;
  const int everywhere = world.min_over_ranks(seen);
  if (world.rank() == 0) std::filesystem::remove(marker, ec);
  if (everywhere == 0)
    throw Error("--out " + out.string() + " is not one folder on every rank" +
                (seen ? std::string() : " (rank " + std::to_string(world.rank()) + " cannot see rank 0's files there)") +
                ": give every rank the same --out, on a filesystem they share");
}

}  // namespace

EvalResult evaluate_on_ranks(Session& session, const Graph& graph, const Registry& registry,
                             const EvalOptions& options) {
  MpiWorld* world = mpi_world();
  if (!world) return session.evaluate(graph, options);
  const int start = graph.time ? graph.time->start : 1;
  const FrameRange range = options.frames ? *options.frames : FrameRange{start, start};
  const std::string& split = mpi_settings().split;
  const GraphView view(graph, registry);
  if (split == "frames" || (split == "auto" && range.last > range.first)) {
    require_shared_output(*world, options.output_dir);  // (tiles: rank 0 alone writes files)
    return evaluate_frames(*world, session, view, options, range);
  }
  return evaluate_tiles(*world, session, view, options, range);
}

int run_sweep_on_ranks(const SweepRequest& request, const RunSettings& settings) {
  MpiWorld* world = mpi_world();
  if (!world) return run_sweep(request, settings);
  if (!request.only.empty() || request.collect) {
    std::cerr << "error: --sweep-points and --sweep-collect are a farm task's options, not for mpirun\n";
    return kInvalid;
  }
  int exit = kOk;
  const auto loaded = load_for_run(settings.graph_path, settings.sets, &exit);
  if (!loaded) return exit;
  const auto count = check_sweep(request, settings, *loaded);
  if (!count) return kInvalid;
  SweepRequest mine = request;
  std::unique_ptr<Dealer> dealer;
  PointDealing dealing;
  if (mpi_settings().deal == "dynamic") {  // a part at a time, as this rank asks
    dealer = world->dealer(long(*count));
    dealing.next = [&, part = Dealer::Part{}]() mutable {  // the points of this rank's parts, one at a time
      if (part.empty()) part = dealer->next();
      return part.empty() ? -1L : part.begin++;
    };
    dealing.evaluate = [&](const std::function<EvalResult()>& evaluate) {
      return world->rank() == 0 ? evaluate_answering(*dealer, evaluate) : evaluate();
    };
    mine.dealt = &dealing;
  } else {  // round-robin
    for (std::size_t i = std::size_t(world->rank()); i < *count; i += std::size_t(world->size()))
      mine.only += (mine.only.empty() ? "" : ",") + std::to_string(i);
  }
  const auto start = std::chrono::steady_clock::now();
  int code = mine.only.empty() && !mine.dealt ? kOk : run_sweep(mine, settings);
  if (code == kInterrupted) world->abort(kInterrupted);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (dealer) {
    dealer->report(std::to_string(*count) + " sweep points");
    dealer.reset();
  }
  report_balance(*world, "sweep points", world->gather_all(seconds));
  code = world->max_over_ranks(code);  // every rank's points are written
  if (world->rank() == 0) {
    SweepRequest tables = request;
    tables.collect = true;
    code = std::max(code, run_sweep(tables, settings));
  }
  return code;
}

}  // namespace loom::runner
