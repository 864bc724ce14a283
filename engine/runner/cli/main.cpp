// The `loom` command: run, validate, list nodes and plugins, describe image files.
// Its exit codes: cli/exit_codes.hpp.
#include <atomic>
#include <cstdio>
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/command_names.hpp"
#include "cli/group_listing.hpp"
#include "cli/image_info.hpp"
#include "cli/new_plugin.hpp"
#include "cli/node_reference.hpp"
#include "cli/preview.hpp"
#include "cli/profile.hpp"
#include "cli/progress.hpp"
#include "cli/run_settings.hpp"
#include "cli/signals.hpp"
#include "cli/target_json.hpp"
#include "cli/watch.hpp"
#include "farm/child_process.hpp"
#include "farm/farm_commands.hpp"
#include "loom/atomic_file.hpp"
#include "loom/disk_cache.hpp"
#include "loom/evaluator.hpp"
#include "loom/graph.hpp"
#include "loom/graph_view.hpp"
#include "loom/plugin_loader.hpp"
#include "loom/process_start.hpp"
#include "loom/suggest.hpp"
#include "mpi/mpi_run.hpp"
#include "sweep/sweep.hpp"

namespace {

using loom::runner::kOk, loom::runner::kNodeFailed, loom::runner::kInvalid, loom::runner::kPluginError,
    loom::runner::kInterrupted;

using loom::runner::RunSettings;

// The evaluation options of `loom run` as `s` asks: frames, targets, threads,
// output folder, cancellation; the disk cache is opened into `disk`. Nullopt,
// after saying why, for a malformed --frames or a folder that is not a cache.
std::optional<loom::EvalOptions> run_options(const RunSettings& s, const loom::Graph& graph,
                                             std::optional<loom::DiskCache>& disk) {
  loom::EvalOptions options;
  if (!s.frames.empty()) {
    options.frames = loom::runner::parse_frame_range(s.frames);
    if (!options.frames) {
      std::cerr << "error: --frames: expected A-B or A (whole frame numbers, A <= B), got \"" << s.frames << "\"\n";
      return std::nullopt;
    }
  } else if (graph.time) {
    options.frames = loom::FrameRange{graph.time->start, graph.time->end};
  }
  if (options.frames)
    if (auto problem = loom::runner::frame_count_problem(*options.frames,
                                                         s.frames.empty() ? "the graph's time range" : "--frames")) {
      std::cerr << "error: " << *problem << "\n";
      return std::nullopt;
    }
  if (!s.cache.disabled) {
    try {
      disk.emplace(s.cache.options());
    } catch (const loom::Error& e) {  // a folder that is not a Loom cache
      std::cerr << "error: " << e.what() << "\n";
      return std::nullopt;
    }
    options.disk_cache = &*disk;
  }
  for (const auto& t : s.targets) options.targets.push_back(loom::parse_target(t));
  options.threads = s.threads;
  options.output_dir = std::filesystem::absolute(s.out_dir);
  options.allow_outside_output = s.allow_outside;
  options.cancel = &loom::runner::cancel_flag();
  return options;
}

// What a run prints when it ends: failed nodes, the requested outputs (rank 0
// of an MPI run only) and, unless quiet, the counts.
void print_result(const RunSettings& s, const loom::Graph& graph, const loom::Registry& registry,
                  const loom::EvalResult& result, double total) {
  std::map<std::string, int> counts;
  for (const auto& [id, r] : result.nodes) {
    const std::string status = loom::runner::status_text(r, result);
    ++counts[status];
    if (status == "failed")
      std::cerr << "error: node \"" << id << "\" (" << graph.nodes.at(id).type << ") failed: " << r.error
                << "\n";
  }
  if (loom::runner::mpi_rank() == 0)
    std::cout << (s.print_json ? loom::runner::target_json(graph, registry, result)
                               : loom::runner::target_lines(graph, registry, result));
  if (s.quiet || loom::runner::mpi_rank() > 0) return;  // an MPI run's summary is rank 0's
  const std::string over = result.frames > 1 ? " over " + std::to_string(result.frames) + " frames" : "";
  const std::string cancelled = counts["cancelled"] ? ", " + std::to_string(counts["cancelled"]) + " cancelled" : "";
  std::fprintf(stderr, "%d ran, %d cached, %d pruned, %d skipped, %d failed%s%s in %.3f s\n", counts["ran"],
               counts["cached"], counts["pruned"], counts["skipped"], counts["failed"], cancelled.c_str(), over.c_str(),
               total);
}

int cmd_run(const RunSettings& s) {
  const auto start = std::chrono::steady_clock::now();
  int exit = kOk;
  auto loaded = loom::runner::load_for_run(s.graph_path, s.sets, &exit);
  if (!loaded) return exit;
  const loom::Registry& registry = *loaded->registry;
  const loom::Graph& graph = loaded->graph;
  const loom::GraphView view(graph, registry);
  std::optional<loom::DiskCache> disk;
  auto options = run_options(s, graph, disk);
  if (!options) return kInvalid;
  loom::runner::ConsoleObserver observer(s.quiet || loom::runner::mpi_rank() > 0);
  options->observer = &observer;
  std::optional<loom::runner::PreviewWriter> preview;
  if (!s.preview_path.empty() && loom::runner::mpi_rank() == 0) {
    const loom::NodeType* save = loom::runner::save_image_type(*loaded);
    if (!save) return kPluginError;
    options->observer = &preview.emplace(observer, *save, s.preview_path, s.preview_every);
  }
  if (options->targets.empty() && view.sinks().empty())
    std::cerr << "warning: " << s.graph_path
              << " has no sink nodes (e.g. SaveImage): nothing to run; name outputs with --target\n";

  loom::runner::stop_on_signals(loom::runner::mpi_world() ? loom::runner::Grace::ranks : loom::runner::Grace::brief);
  loom::EvalResult result;
  try {
    loom::Session session(registry);
    result = loom::runner::evaluate_on_ranks(session, graph, registry, *options);
  } catch (const std::exception& e) {
    loom::runner::nodes_returned();
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  }
  loom::runner::nodes_returned();
  observer.stop();
  if (disk && !s.cache.no_trim && disk->bytes_written() > 0) disk->trim();  // a run that stored nothing scans nothing
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print_result(s, graph, registry, result, total);
  if (!s.profile_path.empty()) {
    try {
      loom::write_file_atomic(s.profile_path, loom::runner::profile_json(graph, result, total,
                                                                         loaded->loader->loaded_names(),
                                                                         disk ? &*disk : nullptr)
                                                  .dump(2) +
                                                  "\n");
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

int cmd_cache(const std::string& action, const loom::runner::CacheSettings& settings) try {
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

void add_cache_options(CLI::App* app, loom::runner::CacheSettings& cache) {
  app->add_option("--cache", cache.dir, "persistent cache folder (default: $XDG_CACHE_HOME/loom)");
  app->add_option("--cache-limit", cache.limit_mb, "cache size limit in MB (least recently used out)")
      ->capture_default_str()
      ->check(loom::runner::number_above(0));
}

// `loom run`'s command line, one option per line, read top to bottom like `loom run --help`.
CLI::App* add_run_command(CLI::App& app, RunSettings& s, loom::runner::SweepRequest& sweep, bool& watch) {
  auto* run = app.add_subcommand("run", "Run a graph: evaluate its sinks (or --target outputs).");
  run->add_option("graph", s.graph_path, "graph file (JSON)")->required();
  run->add_option("--out", s.out_dir, "folder for output files (relative output paths)")->capture_default_str();
  run->add_option("--set", s.sets, "override an input: ID.INPUT=JSON (repeatable)");
  run->add_option("--target", s.targets, "evaluate ID or ID.OUTPUT instead of the sinks (repeatable)");
  run->add_option("--threads", s.threads, "worker threads (0: all cores)")
      ->check(loom::runner::whole_number_at_least(0));
  run->add_option("--profile", s.profile_path, "write a JSON profile of the run to this file (with --sweep: per point)");
  run->add_flag("--quiet,-q", s.quiet, "print only errors and requested outputs");
  run->add_flag("--json", s.print_json, "print the requested outputs as one JSON object, each value in full");
  run->add_flag("--watch", watch,
                "run again whenever the graph, a group file, a Python node module or an input file it reads "
                "changes; Ctrl-C ends");
  run->add_option("--preview", s.preview_path,
                  "write the partial images nodes publish while they run (PathTrace after each pass) to this "
                  "file, atomically; sinks still write the final results");
  run->add_option("--preview-every", s.preview_every, "with --preview: seconds between writes at least")
      ->capture_default_str()
      ->check(loom::runner::number_at_least(0));
  run->add_option("--frames", s.frames, "frames to run, A-B or A (default: the graph's \"time\" range)");
  add_cache_options(run, s.cache);
  run->add_flag("--no-cache", s.cache.disabled, "neither read nor write the persistent cache");
  run->add_option("--cache-min-seconds", s.cache.min_seconds,
                  "store only results whose node takes this long over the run's frames (docs/time.md)")
      ->capture_default_str()
      ->check(loom::runner::number_at_least(0));
  run->add_flag("--cache-no-trim", s.cache.no_trim, "never trim the cache to its limit (farm workers sharing one)");
  run->add_flag("--allow-outside-out", s.allow_outside,
                "let output paths be absolute or climb out of --out with \"..\" (refused otherwise)");
  loom::runner::add_sweep_options(run, sweep);
  loom::runner::add_mpi_options(run);
  return run;
}

// Longer than our ~80-line rule on purpose: it is the command line's
// declaration, one option per line, read top to bottom like `loom --help`.
static int loom_main(int argc, char** argv) {
  CLI::App app{std::string("loom: run graphs of computer-graphics nodes.\n") + loom::runner::kExitCodesText};
  app.require_subcommand(1);

  std::string graph_path, type, manifest_lib, manifest_out;
  bool as_json = false, as_markdown = false, watch = false;
  RunSettings settings;
  loom::runner::SweepRequest sweep;
  auto* run = add_run_command(app, settings, sweep, watch);
  auto* cache_cmd = app.add_subcommand("cache", "Show or clear the persistent result cache.");
  std::string cache_action;
  cache_cmd->add_option("action", cache_action, "info or clear")->required()->check(CLI::IsMember({"info", "clear"}));
  add_cache_options(cache_cmd, settings.cache);

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

  std::vector<std::string> info_files;
  auto* info = app.add_subcommand("info", "Print image files' layers and channels, and the node, seed and frame "
                                          "that made them.");
  info->add_option("file", info_files, "image files (EXR, PNG, TIFF, JPEG, ...)")->required();

  std::string plugin_name, plugin_dir = ".";
  auto* scaffold = app.add_subcommand("new-plugin", "Write a new plugin to start from: builds and tests as written.");
  scaffold->add_option("name", plugin_name, "plugin name: a-z, 0-9 and _, starting with a letter")->required();
  scaffold->add_option("--dir", plugin_dir, "create the plugin in DIR/NAME")->capture_default_str();

  auto farm = loom::runner::add_farm_commands(app);
  loom::runner::refuse_options_as_values(app);

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
    loom::runner::stop_on_signals(loom::runner::Grace::none);  // waiting for a change is not a run to end at once
    return loom::runner::watch(settings.graph_path, loom::runner::cancel_flag(), [&] { return cmd_run(settings); });
  }
  if (farm->chosen()) return farm->run();
  if (*run && sweep.active()) return loom::runner::run_sweep_on_ranks(sweep, settings);
  if (*run) return cmd_run(settings);
  if (*cache_cmd) return cmd_cache(cache_action, settings.cache);
  if (*validate) return cmd_validate(graph_path);
  if (*nodes) return cmd_nodes(type, as_json, as_markdown);
  if (*plugins) return cmd_plugins(manifest_lib, manifest_out);
  if (*info) return loom::runner::image_info(info_files);
  if (*scaffold) return loom::runner::new_plugin(plugin_name, plugin_dir);
  return kInvalid;
}

// The commands that evaluate graphs, and so allocate what a graph needs: a
// run, and the local dispatcher of `submit` and `jobs resume`, whose tasks
// are forks of it, run on huge pages (loom/process_start.hpp). The others
// (--help, nodes, validate, info...) start once.
static bool evaluates_graphs(char** argv) {
  const std::string command = argv[0] && argv[1] ? argv[1] : "";
  return command == "run" || command == "submit" || command == "jobs";
}

// The local dispatcher runs a task's `loom run` in a fork of itself, through
// this same function (farm/child_process.hpp, start_loom).
int main(int argc, char** argv) {
  loom::prepare_process(argv, evaluates_graphs(argv));
  loom::runner::set_loom_main(&loom_main);
  return loom_main(argc, argv);
}
