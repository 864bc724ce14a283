// Author and host API. loom::testing: run graphs in-process from a plugin's own tests, inside or
// outside the Loom tree. Installed with the SDK as the CMake target
// loom::testing; loom_add_plugin(... TESTS a_test.cpp) links it for you.
//
//   loom::testing::Engine engine;  // Loom's plugins + this build's plugins
//   loom::testing::GraphBuilder g;
//   g.node("board", "Checkerboard").set("size", {64, 64});
//   g.node("poster", "Posterize").link("image", "board.image").set("levels", 2);
//   loom::testing::Run run = engine.run(g, {"poster.image"});
//   ASSERT_TRUE(run.ok()) << run.errors();
//   const loom::Image& out = run.output<loom::Image>("poster.image");
//
// Independent of any test framework: errors are exceptions (loom::Error,
// loom::GraphError) whose messages say what went wrong.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "loom/evaluator.hpp"
#include "loom/graph.hpp"
#include "loom/plugin_loader.hpp"

// loom_add_plugin(... TESTS ...) defines this as the build's plugin folder, so
// a test finds the plugin it tests without any environment variable.
#ifndef LOOM_TESTING_PLUGIN_DIR
#define LOOM_TESTING_PLUGIN_DIR ""
#endif

namespace loom::testing {

// Builds a graph document in C++; the same JSON a graph file holds.
class LOOM_API GraphBuilder {
 public:
  class LOOM_API NodeRef {
   public:
    NodeRef& set(const std::string& input, const json& literal);
    // Links an input to "ID.OUTPUT" (or "ID" for a node's only output).
    NodeRef& link(const std::string& input, const std::string& from);

   private:
    friend class GraphBuilder;
    explicit NodeRef(json& node) : node_(&node) {}
    json* node_;
  };

  NodeRef node(const std::string& id, const std::string& type);
  GraphBuilder& seed(std::uint64_t seed);
  const json& document() const { return document_; }

 private:
  json document_ = {{"loom", 1}, {"nodes", json::object()}};
};

// The outcome of one evaluation: every node's status, the targets' outputs.
class LOOM_API Run {
 public:
  explicit Run(EvalResult result) : result_(std::move(result)) {}

  bool ok() const { return result_.ok(); }
  NodeStatus status(const std::string& node) const;  // throws for an unknown id
  const std::string& error(const std::string& node) const;
  const std::vector<std::string>& warnings(const std::string& node) const;
  // Every failed or skipped node with its error, one per line ("" when ok).
  std::string errors() const;

  // A target's value: "ID.OUTPUT", or "ID" when the node has one output.
  Value value(const std::string& target) const;
  template <class T>
  const T& output(const std::string& target) const {
    const Value& v = stored(target);
    return v.as<T>();
  }

  const EvalResult& result() const { return result_; }

 private:
  const Value& stored(const std::string& target) const;
  EvalResult result_;
};

class LOOM_API Engine {
 public:
  // Plugins come from Loom's own plugin folder (beside the installed
  // libloom_testing), then `plugin_dirs` (by default the folder
  // loom_add_plugin builds into), then LOOM_PLUGIN_PATH.
  explicit Engine(std::vector<std::filesystem::path> plugin_dirs = {LOOM_TESTING_PLUGIN_DIR});
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Parses, loads the plugins the graph uses and validates it; throws
  // loom::GraphError (with "did you mean" for unknown types).
  Graph load(const json& document, const std::filesystem::path& file = "test.json");

  // Evaluates the targets ("ID" or "ID.OUTPUT"), or every sink when empty.
  // Output files of sinks go to `out`, by default to output_dir().
  Run run(const json& document, const std::vector<std::string>& targets = {},
          const std::filesystem::path& out = {});
  Run run(const GraphBuilder& graph, const std::vector<std::string>& targets = {},
          const std::filesystem::path& out = {});
  // A graph load() returned: one loaded from a named file (relative paths
  // resolve against it), or run twice to see what the cache kept.
  Run run(const Graph& graph, const std::vector<std::string>& targets = {}, const std::filesystem::path& out = {});

  // One output, throwing loom::Error with the node's error if it did not run.
  template <class T>
  T output(const json& document, const std::string& target) {
    return value(document, target).as<T>();
  }
  template <class T>
  T output(const GraphBuilder& graph, const std::string& target) {
    return value(graph.document(), target).as<T>();
  }
  // The same as a Value: its type, its summary, or only whether it throws.
  Value value(const json& document, const std::string& target);

  // Loads the plugins that declare these node types, so registry() knows them
  // without a graph being run (a front end's or a tool's own tests).
  void load_plugins(const std::vector<std::string>& node_types);
  void load_all_plugins();

  // The Session every run goes through, for what run() does not ask:
  // threads, frames, an observer, cancellation, the disk cache, and what the
  // cache holds (cached_frames, cache_entries).
  Session& session();

  // A temporary folder for sinks' files, removed when the Engine is destroyed
  // (pass `out` to run() to keep them).
  std::filesystem::path output_dir();
  const std::vector<std::filesystem::path>& plugin_path() const;
  std::vector<std::string> loaded_plugins() const;
  const Registry& registry() const;
  Registry& registry();  // to add a node type the test itself declares

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Loom's own plugin folder: <dir of libloom_testing>/loom/plugins.
LOOM_API std::filesystem::path installed_plugin_dir();

}  // namespace loom::testing
