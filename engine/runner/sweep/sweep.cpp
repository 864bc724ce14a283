#include "sweep/sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli/profile.hpp"
#include "cli/signals.hpp"
#include "cli/target_json.hpp"
#include "loom/atomic_file.hpp"
#include "mpi/mpi_run.hpp"
#include "sweep/sweep_axes.hpp"
#include "sweep/sweep_table.hpp"

namespace loom::runner {
namespace fs = std::filesystem;

void add_sweep_options(CLI::App* run, SweepRequest& r) {
  auto* sweep = run->add_option("--sweep", r.axes,
                  "run at every value: ID.INPUT=V1,V2,... (JSON values) or A:B:N or A:B:N:log (repeatable: "
                  "the Cartesian product); writes OUT/points/NNNN/, OUT/sweep.csv and OUT/sweep.json");
  run->add_flag("--zip", r.zip, "with several --sweep: the i-th values together, not every combination")
      ->needs(sweep);
  run->add_option("--record", r.records, "with --sweep: keep ID.OUTPUT (or every output of ID) of each point")
      ->needs(sweep);
  run->add_option("--plot", r.plots, "with --sweep: draw column X against column Y of sweep.csv (X:Y) as a PNG")
      ->needs(sweep);
  run->add_option("--sweep-points", r.only, "with --sweep: run only these points (I,J,...; a submitted task)")
      ->group("")->needs(sweep);
  run->add_flag("--sweep-collect", r.collect, "with --sweep: write the tables from the points' files only")
      ->group("")->needs(sweep);
}

namespace {

fs::path point_dir(const fs::path& out, std::size_t index) {
  char name[16];
  std::snprintf(name, sizeof name, "%04zu", index);
  return out / "points" / name;
}

struct Plan {
  std::vector<SweepAxis> axes;
  std::vector<SweepPoint> points;
  std::vector<Graph> graphs;  // one per point, values applied and validated
  std::vector<Target> targets;
  std::vector<bool> selected;
};

// Every point's graph is built and validated before any runs.
int plan_sweep(const SweepRequest& r, const RunSettings& s, const LoadedGraph& g, Plan* plan) {
  try {
    const GraphView view(g.graph, *g.registry);
    for (const auto& spec : r.axes) {
      plan->axes.push_back(parse_sweep_axis(spec, view));
      for (std::size_t k = 0; k + 1 < plan->axes.size(); ++k)
        if (plan->axes[k].input == plan->axes.back().input)
          throw Error("--sweep " + spec + ": " + plan->axes.back().input +
                      " is swept twice (give its values in one --sweep)");
    }
    plan->points = sweep_points(plan->axes, r.zip);  // counted, and refused past the limit, first
    std::optional<FrameRange> frames = s.frames.empty() ? std::optional<FrameRange>() : parse_frame_range(s.frames);
    if (s.frames.empty() && g.graph.time) frames = FrameRange{g.graph.time->start, g.graph.time->end};
    if (frames)
      if (auto problem = frame_count_problem(*frames, s.frames.empty() ? "the graph's time range" : "--frames"))
        throw Error(*problem);
    for (const auto& p : r.plots)
      if (p.find(':') == std::string::npos || p.front() == ':' || p.back() == ':')
        throw Error("--plot " + p + ": expected X:Y, two columns of sweep.csv (e.g. arap.seconds:arap.energy)");
    plan->selected.assign(plan->points.size(), r.only.empty());
    std::istringstream only(r.only);
    for (std::string part; std::getline(only, part, ',');) {
      const std::size_t i = std::stoul(part);
      if (i >= plan->points.size()) throw Error("--sweep-points: no point " + part);
      plan->selected[i] = true;
    }
    for (const auto& point : plan->points) {
      Graph graph = g.graph;
      for (const auto& a : point.assignments) set_input(graph, a);
      validate_graph(graph, *g.registry, g.loader->searched_description(), g.loader->known_node_types());
      plan->graphs.push_back(std::move(graph));
    }
    for (const auto& t : s.targets.empty() ? view.sinks() : s.targets) plan->targets.push_back(parse_target(t));
    for (const auto& rec : r.records) {
      try {
        view.outputs(rec);
      } catch (const Error& e) {
        throw Error("--record " + rec + ": " + e.what());
      }
      plan->targets.push_back(parse_target(rec));
    }
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  }
  return kOk;
}

// The recorded outputs of one point, as JSON (opaque values by their summary).
json recorded_values(const SweepRequest& r, const Graph& graph, const Registry& registry, const EvalResult& result) {
  json records = json::object();
  const GraphView view(graph, registry);
  const auto named = named_outputs_per_frame(view, result);
  for (const auto& rec : r.records)
    for (const ResolvedOutput& o : view.outputs(rec))
      for (const auto& [name, values] : named) {
        if (name != o.name && !(o.target.output.empty() && name.rfind(o.name + ".", 0) == 0)) continue;
        if (values.size() == 1) {
          records[name] = value_json(values[0]);
          continue;
        }
        json frames = json::array();  // kept at several frames: one entry per frame
        for (const Value& v : values) frames.push_back(value_json(v));
        records[name] = std::move(frames);
      }
  return records;
}

// Where a node's results in this point came from: computed in this run, read
// from the disk cache (a rerun), or both over its frames (a resumed run).
const char* source_of(const NodeReport& r) {
  if (r.disk_hits == 0) return "computed";
  return r.runs == 0 ? "cached" : "resumed";
}

// One point: its outputs in OUT/points/NNNN, its point.json, and with
// --profile its profile in `profiles` (by point index).
json run_point(const SweepRequest& r, const RunSettings& s, const Plan& plan, std::size_t i, Session& session,
               const LoadedGraph& g, DiskCache* disk, json& profiles) {
  const Registry& registry = *g.registry;
  EvalOptions options;
  options.targets = plan.targets;
  options.threads = s.threads;
  options.output_dir = fs::absolute(point_dir(s.out_dir, i));
  options.allow_outside_output = s.allow_outside;
  options.cancel = &cancel_flag();
  options.disk_cache = disk;
  const Graph& graph = plan.graphs[i];
  if (!s.frames.empty()) options.frames = parse_frame_range(s.frames);
  else if (graph.time) options.frames = FrameRange{graph.time->start, graph.time->end};
  fs::create_directories(options.output_dir);
  const auto start = std::chrono::steady_clock::now();
  const auto evaluate = [&] { return session.evaluate(graph, options); };
  EvalResult result = r.dealt ? r.dealt->evaluate(evaluate) : evaluate();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  json nodes = json::object();
  double compute = 0;
  // Nodes computed in this run and nodes read from the disk cache: the
  // point's source. Sinks always run (they write files), so they say nothing of it.
  int computed = 0, read = 0;
  const GraphView view(graph, registry);
  for (const auto& [id, report] : result.nodes) {
    if (report.status == NodeStatus::pruned) continue;
    nodes[id] = {{"status", status_text(report, result)},
                 {"seconds", report.compute_seconds},
                 {"source", source_of(report)}};
    if (!report.error.empty()) nodes[id]["error"] = report.error;
    compute += report.compute_seconds;
    if (view.type(id).spec.sink) continue;
    computed += report.runs > 0;
    read += report.disk_hits > 0;
  }
  json point = {{"index", i},
                {"values", plan.points[i].values},
                {"status", result.cancelled ? "cancelled" : result.ok() ? "ok" : "failed"},
                {"source", read == 0 ? "computed" : computed == 0 ? "cached" : "resumed"},
                {"seconds", compute},
                {"run_seconds", wall},
                {"nodes", std::move(nodes)},
                {"records", recorded_values(r, graph, registry, result)}};
  write_file_atomic(options.output_dir / "point.json", point.dump(2) + "\n");
  if (!s.profile_path.empty())
    profiles[std::to_string(i)] = profile_json(graph, result, wall, g.loader->loaded_names(), disk);
  return point;
}

// Why a point failed, also with -q (as `loom run` prints a failed node):
// point.json alone left a quiet sweep's exit 1 unexplained.
void print_failures(const json& point, std::size_t i) {
  if (point["status"] != "failed") return;
  for (const auto& [id, node] : point["nodes"].items())
    if (node.value("status", "") == "failed" && node.contains("error"))
      std::fprintf(stderr, "error: point %zu (%s): node \"%s\" failed: %s\n", i, point["values"].dump().c_str(),
                   id.c_str(), node["error"].get<std::string>().c_str());
}

json read_point(const fs::path& out, std::size_t i, const SweepPoint& p) {
  std::ifstream in(point_dir(out, i) / "point.json");
  json point = in ? json::parse(in, nullptr, false) : json();
  if (!point.is_object()) return {{"index", i}, {"values", p.values}, {"status", "missing"}};
  return point;
}

// The points run, and the others' read from their files (for the tables):
// the selected points in order, or those `r.dealt` hands out (marked
// selected as they come).
std::vector<json> run_points(const SweepRequest& r, const RunSettings& s, Plan& plan, Session& session,
                             const LoadedGraph& g, DiskCache* disk, json& profiles) {
  std::vector<json> points;
  const std::size_t selected =
      r.collect ? 0 : static_cast<std::size_t>(std::count(plan.selected.begin(), plan.selected.end(), true));
  std::size_t done = 0;
  auto run = [&](std::size_t i) {
    plan.selected[i] = true;
    points.push_back(run_point(r, s, plan, i, session, g, disk, profiles));
    print_failures(points.back(), i);
    if (s.quiet) return;
    // Points are numbered from 0 everywhere (points/0003, --sweep-points 3,
    // `loom jobs status`); the bracket counts this run's progress.
    const std::string of = r.dealt ? "" : "/" + std::to_string(selected);
    std::fprintf(stderr, "[%zu%s] point %zu (%s): %s, %s, in %.3f s\n", ++done, of.c_str(), i,
                 plan.points[i].values.dump().c_str(), points.back()["status"].get<std::string>().c_str(),
                 points.back()["source"].get<std::string>().c_str(), points.back()["run_seconds"].get<double>());
  };
  if (r.dealt && !r.collect) {
    for (long i; !cancel_flag() && (i = r.dealt->next()) >= 0;) run(std::size_t(i));
    return points;
  }
  for (std::size_t i = 0; i < plan.points.size(); ++i) {
    // Cancelled: stop at once. Reading the remaining points' files and writing
    // the tables took seconds for a large sweep (4.2 s at 300,000 points).
    if (cancel_flag()) break;
    if (!plan.selected[i] || r.collect)
      points.push_back(read_point(s.out_dir, i, plan.points[i]));
    else
      run(i);
  }
  return points;
}

}  // namespace

std::optional<std::size_t> check_sweep(const SweepRequest& r, const RunSettings& s, const LoadedGraph& g) {
  Plan plan;
  if (plan_sweep(r, s, g, &plan) != kOk) return std::nullopt;
  return plan.points.size();
}

int run_sweep(const SweepRequest& r, const RunSettings& s) {
  int exit = kOk;
  auto g = load_for_run(s.graph_path, s.sets, &exit);
  if (!g) return exit;
  Plan plan;
  if (int code = plan_sweep(r, s, *g, &plan); code != kOk) return code;
  if (!s.frames.empty() && !parse_frame_range(s.frames)) {
    std::cerr << "error: --frames: expected A-B or A (whole frame numbers, A <= B), got \"" << s.frames << "\"\n";
    return kInvalid;
  }
  std::optional<DiskCache> disk;
  if (!s.cache.disabled) disk.emplace(s.cache.options());
  stop_on_signals(mpi_world() ? Grace::ranks : Grace::brief);
  Session session(*g->registry);
  json profiles = json::object();
  const auto start = std::chrono::steady_clock::now();
  const std::vector<json> points = run_points(r, s, plan, session, *g, disk ? &*disk : nullptr, profiles);
  nodes_returned();
  if (cancel_flag()) {
    std::cerr << interrupted_message() << "\nthe sweep's tables were not written: --sweep-collect writes them "
                                         "from the points done\n";
    return kInterrupted;
  }
  if (disk && !s.cache.no_trim && disk->bytes_written() > 0) disk->trim();
  if (!s.profile_path.empty() && !r.collect) {  // a profile per point run, by index
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    try {
      write_file_atomic(s.profile_path, json{{"total_seconds", total}, {"points", profiles}}.dump(2) + "\n");
    } catch (const Error& e) {
      std::cerr << "error: " << e.what() << "\n";
      exit = kNodeFailed;
    }
  }
  if ((r.only.empty() && !r.dealt) || r.collect) {
    if (!write_sweep_tables(s.out_dir, plan.axes, points, r.plots, s.quiet)) exit = kNodeFailed;
  }
  if (cancel_flag()) {  // while the tables were written
    std::cerr << interrupted_message() << "\n";
    return kInterrupted;
  }
  for (const json& point : points)
    if (plan.selected[point["index"].get<std::size_t>()] && point["status"] != "ok") exit = kNodeFailed;
  return exit;
}

}  // namespace loom::runner
