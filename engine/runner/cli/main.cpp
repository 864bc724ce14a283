// The `loom` command: run, validate, list nodes and plugins.
//
// Exit codes: 0 success; 1 a node failed (other outputs still written);
// 2 invalid graph or usage; 3 plugin load error; 130 interrupted.
#include <atomic>
#include <cstdio>
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>

#include "loom/atomic_file.hpp"
#include "loom/disk_cache.hpp"
#include "loom/evaluator.hpp"
#include "loom/graph.hpp"
#include "loom/graph_view.hpp"
#include "loom/plugin_loader.hpp"
#include "loom/suggest.hpp"
#include "cli/command_names.hpp"
#include "cli/new_plugin.hpp"
#include "cli/node_reference.hpp"
#include "cli/target_json.hpp"
#include "cli/profile.hpp"
#include "cli/progress.hpp"
#include "cli/signals.hpp"
#include "cli/watch.hpp"
#include "cli/run_settings.hpp"
#include "farm/farm_commands.hpp"
#include "cli/group_listing.hpp"
#include "sweep/sweep.hpp"
#include "mpi/mpi_run.hpp"

namespace {

using loom::runner::kOk, loom::runner::kNodeFailed, loom::runner::kInvalid, loom::runner::kPluginError,
    loom::runner::kInterrupted;

// Where the persistent cache lives and how it behaves (`--cache`, `--no-cache`).
struct CacheSettings {
  std::string dir;  // empty: the default folder
  bool disabled = false;
  bool no_trim = false;  // a farm worker: the assemble task trims
  double limit_mb = 10240;
  double min_seconds = 0.05;

  loom::DiskCache::Options options() const {
    loom::DiskCache::Options o;
    o.dir = dir.empty() ? loom::DiskCache::default_dir() : std::filesystem::path(dir);
    o.max_bytes = static_cast<std::uint64_t>(limit_mb * 1024 * 1024);
    o.min_seconds = min_seconds;
    if (min_seconds == 0) o.read_mb_per_s = 1e300;  // store every result, however cheap to recompute
    return o;
  }
};

int cmd_run(const std::string& graph_path, const std::string& out_dir,
            const std::vector<std::string>& sets, const std::vector<std::string>& targets,
            int threads, const std::string& profile_path, bool quiet, const std::string& frames,
            const CacheSettings& cache, bool allow_outside, bool print_json) {
  auto start = std::chrono::steady_clock::now();
  quiet = quiet || loom::runner::mpi_rank() > 0;  // an MPI run's summary is rank 0's
  int exit = kOk;
  auto loaded = loom::runner::load_for_run(graph_path, sets, &exit);
  if (!loaded) return exit;
  const loom::Registry& registry = *loaded->registry;
  const loom::PluginLoader& loader = *loaded->loader;
  const loom::Graph& graph = loaded->graph;

  loom::EvalOptions options;
  if (!frames.empty()) {
    options.frames = loom::runner::parse_frame_range(frames);
    if (!options.frames) {
      std::cerr << "error: --frames: expected A-B or A (whole frame numbers, A <= B), got \"" << frames << "\"\n";
      return kInvalid;
    }
  } else if (graph.time) {
    options.frames = loom::FrameRange{graph.time->start, graph.time->end};
  }
  if (options.frames)
    if (auto problem = loom::runner::frame_count_problem(*options.frames, frames.empty() ? "the graph's time range" : "--frames")) {
      std::cerr << "error: " << *problem << "\n";
      return kInvalid;
    }
  std::optional<loom::DiskCache> disk;
  if (!cache.disabled) {
    try {
      disk.emplace(cache.options());
    } catch (const loom::Error& e) {  // a folder that is not a Loom cache
      std::cerr << "error: " << e.what() << "\n";
      return kInvalid;
    }
    options.disk_cache = &*disk;
  }
  for (const auto& t : targets) options.targets.push_back(loom::parse_target(t));
  options.threads = threads;
  options.output_dir = std::filesystem::absolute(out_dir);
  options.allow_outside_output = allow_outside;
  options.cancel = &loom::runner::cancel_flag();
  loom::runner::ConsoleObserver observer(quiet);
  options.observer = &observer;
  if (options.targets.empty()) {
    if (loom::GraphView(graph, registry).sinks().empty())
      std::cerr << "warning: " << graph_path
                << " has no sink nodes (e.g. SaveImage): nothing to run; name outputs with --target\n";
  }

  loom::runner::stop_on_signals();
  loom::EvalResult result;
  try {
    loom::Session session(registry);
    result = loom::runner::evaluate_on_ranks(session, graph, registry, options);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  }
  observer.stop();
  if (disk && !cache.no_trim && disk->bytes_written() > 0) disk->trim();  // a run that stored nothing scans nothing

  std::map<loom::NodeStatus, int> counts;
  for (const auto& [id, r] : result.nodes) {
    ++counts[r.status];
    if (r.status == loom::NodeStatus::failed)
      std::cerr << "error: node \"" << id << "\" (" << graph.nodes.at(id).type << ") failed: " << r.error
                << "\n";
  }
  if (loom::runner::mpi_rank() == 0)  // an MPI run prints rank 0's
    std::cout << (print_json ? loom::runner::target_json(graph, registry, result)
                             : loom::runner::target_lines(graph, registry, result));
  double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!quiet) {
    std::string over = result.frames > 1 ? " over " + std::to_string(result.frames) + " frames" : "";
    std::fprintf(stderr, "%d ran, %d cached, %d pruned, %d skipped, %d failed%s in %.3f s\n",
                 counts[loom::NodeStatus::ran], counts[loom::NodeStatus::cached],
                 counts[loom::NodeStatus::pruned], counts[loom::NodeStatus::skipped],
                 counts[loom::NodeStatus::failed], over.c_str(), total);
  }
  if (!profile_path.empty()) {
    const loom::json profile =
        loom::runner::profile_json(graph, result, total, loader.loaded_names(), disk ? &*disk : nullptr);
    try {
      loom::write_file_atomic(profile_path, profile.dump(2) + "\n");
    } catch (const loom::Error& e) {
      std::cerr << "error: " << e.what() << "\n";
      return kNodeFailed;
    }
  }
  if (result.cancelled) {
    std::cerr << loom::runner::interrupted_message() << "\n";
    return kInterrupted;
  }
  return result.ok() ? kOk : kNodeFailed;
}

int cmd_cache(const std::string& action, const CacheSettings& settings) try {
  loom::DiskCache cache(settings.options());
  if (action == "clear") {
    cache.clear();
    std::cout << "cleared " << cache.options().dir.string() << "\n";
    return kOk;
  }
  const auto stats = cache.stats();
  std::printf("folder:  %s\nentries: %llu\nsize:    %.1f MB of %.0f MB (least recently used out first)\n",
              cache.options().dir.c_str(), static_cast<unsigned long long>(stats.entries),
              static_cast<double>(stats.bytes) / (1024.0 * 1024.0), settings.limit_mb);
  return kOk;
} catch (const loom::Error& e) {
  std::cerr << "error: " << e.what() << "\n";
  return kInvalid;
}

int cmd_validate(const std::string& graph_path) {
  loom::Registry registry;
  loom::PluginLoader loader(registry);
  try {
    loom::Graph graph = loom::load_graph_file(graph_path);
    loader.load_for(loom::node_types_used(graph));
    loom::validate_graph(graph, registry, loader.searched_description(), loader.known_node_types());
    std::cout << graph_path << ": valid (" << graph.nodes.size() << " nodes)\n";
    return kOk;
  } catch (const loom::GraphError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  } catch (const loom::Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kPluginError;
  } catch (const std::exception& e) {  // e.g. a JSON library error
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  }
}

int cmd_nodes(const std::string& type, bool as_json, bool as_markdown) {
  loom::Registry registry;
  loom::PluginLoader loader(registry);
  try {
    loader.load_all();
    if (!type.empty()) loader.load_for({type});  // a type provided on demand (py.MODULE.NAME)
  } catch (const loom::Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kPluginError;
  }
  std::vector<const loom::NodeType*> types;
  const std::vector<loom::NodeType> groups = loom::runner::library_node_types(registry);
  if (type.empty()) {
    types = registry.all();
    for (const auto& g : groups) types.push_back(&g);
  } else if (const auto* t = registry.find(type)) {
    types.push_back(t);
  } else if (auto g = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.spec.name == type; });
             g != groups.end()) {
    types.push_back(&*g);
  } else {
    std::cerr << "error: " << loom::unknown_node_type_message(type, loader.known_node_types(),
                                                              loader.searched_description())
              << "\n";
    return kInvalid;
  }
  if (as_markdown) {
    std::cout << loom::runner::nodes_markdown(types, type.empty());
  } else if (as_json) {
    loom::json all = loom::json::object();
    for (const auto* t : types) all[t->spec.name] = loom::describe_node_type(*t);
    std::cout << all.dump(2) << "\n";
  } else {
    for (const auto* t : types) std::cout << loom::runner::node_text(*t, !type.empty());
  }
  return kOk;
}

int cmd_plugins(const std::string& manifest_library, const std::string& manifest_out) {
  if (!manifest_library.empty()) {
    try {
      loom::Registry scratch;
      loom::json m = loom::PluginLoader::manifest_of(manifest_library, scratch);
      if (manifest_out.empty()) std::cout << m.dump(2) << "\n";
      else loom::write_file_atomic(manifest_out, m.dump(2) + "\n");
      return kOk;
    } catch (const loom::Error& e) {
      std::cerr << "error: " << e.what() << "\n";
      return kPluginError;
    }
  }
  loom::Registry registry;
  loom::PluginLoader loader(registry);
  std::cout << "plugin path:\n";
  for (const auto& d : loader.search_path()) std::cout << "  " << d.string() << "\n";
  for (const auto& w : loader.search_path_warnings()) std::cerr << "warning: plugin path: " << w << "\n";
  std::cout << "plugins:\n";
  for (const auto& p : loader.plugins()) {
    std::cout << "  " << p.name << "  " << p.library.string() << "\n";
    if (!p.description.empty()) std::cout << "    " << p.description << "\n";
    std::string types;
    for (const auto& t : p.node_types) types += (types.empty() ? "" : ", ") + t;
    if (!p.type_prefix.empty()) types += (types.empty() ? "" : ", ") + p.type_prefix + "* (provided when a graph names one)";
    std::cout << "    nodes: " << (types.empty() ? "(no manifest: loaded when needed)" : types) << "\n";
  }
  return kOk;
}

}  // namespace

// Longer than our ~80-line rule on purpose: it is the command line's
// declaration, one option per line, read top to bottom like `loom --help`.
int main(int argc, char** argv) {
  CLI::App app{"loom: run graphs of computer-graphics nodes.\n"
               "Exit codes: 0 ok, 1 a node failed, 2 invalid graph or usage, 3 plugin load error, "
               "130 interrupted."};
  app.require_subcommand(1);

  std::string graph_path, out_dir = "out", profile_path, type, manifest_lib, manifest_out;
  std::vector<std::string> sets, targets;
  int threads = 0;
  bool quiet = false, as_json = false, as_markdown = false, allow_outside = false, watch = false;

  auto* run = app.add_subcommand("run", "Run a graph: evaluate its sinks (or --target outputs).");
  run->add_option("graph", graph_path, "graph file (JSON)")->required();
  run->add_option("--out", out_dir, "folder for output files (relative output paths)")
      ->capture_default_str();
  run->add_option("--set", sets, "override an input: ID.INPUT=JSON (repeatable)");
  run->add_option("--target", targets, "evaluate ID or ID.OUTPUT instead of the sinks (repeatable)");
  run->add_option("--threads", threads, "worker threads (0: all cores)")->check(CLI::NonNegativeNumber);
  run->add_option("--profile", profile_path, "write a JSON profile of the run to this file");
  run->add_flag("--quiet,-q", quiet, "print only errors and requested outputs");
  bool print_json = false;
  run->add_flag("--json", print_json, "print the requested outputs as one JSON object, each value in full");
  std::string frames;
  CacheSettings cache;
  run->add_flag("--watch", watch, "run again whenever the graph or an input file it reads changes; Ctrl-C ends");
  run->add_option("--frames", frames, "frames to run, A-B or A (default: the graph's \"time\" range)");
  auto cache_options = [&cache](CLI::App* app) {
    app->add_option("--cache", cache.dir, "persistent cache folder (default: $XDG_CACHE_HOME/loom)");
    app->add_option("--cache-limit", cache.limit_mb, "cache size limit in MB (least recently used out)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
  };
  cache_options(run);
  run->add_flag("--no-cache", cache.disabled, "neither read nor write the persistent cache");
  run->add_option("--cache-min-seconds", cache.min_seconds,
                  "store only results whose node takes this long over the run's frames (docs/time.md)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--cache-no-trim", cache.no_trim, "never trim the cache to its limit (farm workers sharing one)");
  loom::runner::SweepRequest sweep;
  loom::runner::add_sweep_options(run, sweep);
  loom::runner::add_mpi_options(run);

  auto* cache_cmd = app.add_subcommand("cache", "Show or clear the persistent result cache.");
  std::string cache_action;
  cache_cmd->add_option("action", cache_action, "info or clear")->required()->check(CLI::IsMember({"info", "clear"}));
  cache_options(cache_cmd);
  run->add_flag("--allow-outside-out", allow_outside,
                "let output paths be absolute or climb out of --out with \"..\" (refused otherwise)");

  auto* validate = app.add_subcommand("validate", "Check a graph without running it.");
  validate->add_option("graph", graph_path, "graph file (JSON)")->required();

  auto* nodes = app.add_subcommand("nodes", "List node types, or describe one.");
  nodes->add_option("type", type, "a node type to describe");
  auto* json_flag = nodes->add_flag("--json", as_json, "machine-readable description");
  nodes->add_flag("--markdown", as_markdown, "as Markdown: docs/nodes.md, or the one TYPE given")
      ->excludes(json_flag);

  auto* plugins = app.add_subcommand("plugins", "List plugins on the plugin path.");
  plugins->add_option("--manifest", manifest_lib,
                      "print (or write with --output) the manifest of this plugin library");
  plugins->add_option("--output", manifest_out, "with --manifest: the file to write");

  std::string plugin_name, plugin_dir = ".";
  auto* scaffold = app.add_subcommand("new-plugin", "Write a new plugin to start from: builds and tests as written.");
  scaffold->add_option("name", plugin_name, "plugin name: a-z, 0-9 and _, starting with a letter")->required();
  scaffold->add_option("--dir", plugin_dir, "create the plugin in DIR/NAME")->capture_default_str();

  auto farm = loom::runner::add_farm_commands(app);

  if (auto unknown = loom::runner::unknown_command_message(app, argc, argv)) {
    std::cerr << "error: " << *unknown << "\n";
    return kInvalid;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kOk : kInvalid;
  }
  if (*run)
    if (int refused = loom::runner::start_mpi_if_launched(watch)) return refused;
  if (*run && watch) {
    loom::runner::stop_on_signals(false);  // waiting for a change is not a run to end in 5 s
    return loom::runner::watch(graph_path, loom::runner::cancel_flag(), [&] {
      return cmd_run(graph_path, out_dir, sets, targets, threads, profile_path, quiet, frames, cache, allow_outside, print_json);
    });
  }
  if (farm->chosen()) return farm->run();
  if (*run && sweep.active())
    return loom::runner::run_sweep_on_ranks(sweep, {graph_path, out_dir, sets, targets, threads, quiet, frames,
                                           cache.disabled ? std::nullopt : std::optional(cache.options()),
                                           cache.no_trim, allow_outside, profile_path});
  if (*run) return cmd_run(graph_path, out_dir, sets, targets, threads, profile_path, quiet, frames, cache, allow_outside, print_json);
  if (*cache_cmd) return cmd_cache(cache_action, cache);
  if (*validate) return cmd_validate(graph_path);
  if (*nodes) return cmd_nodes(type, as_json, as_markdown);
  if (*plugins) return cmd_plugins(manifest_lib, manifest_out);
  if (*scaffold) return loom::runner::new_plugin(plugin_name, plugin_dir);
  return kInvalid;
}
