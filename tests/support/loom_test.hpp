// Helpers for tests that run nodes through the real engine: the plugins are
// loaded from the build, graphs are JSON written in the test.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "loom/evaluator.hpp"
#include "loom/plugin_loader.hpp"

namespace loom::test {

// An engine with the build's plugins (and the test-only plugins) on its path.
struct Engine {
  Registry registry;
  PluginLoader loader;
  Session session;
  Engine();

  // Parses, loads the plugins it needs, validates; throws GraphError.
  Graph graph(const json& document, const std::filesystem::path& file = "test.json");
  // Evaluates the given targets ("ID" or "ID.OUTPUT"), or the sinks when empty.
  EvalResult run(const Graph& g, std::vector<std::string> targets = {}, int threads = 0,
                 const std::filesystem::path& out = {});
  // One output value of one node, failing the test if the node did not run.
  Value output(const json& document, const std::string& node_output);
};

// ../shared/data/<relative>, or an empty path when the data is absent.
std::filesystem::path data_file(const std::string& relative);
// Skips the current test when the data file is absent.
#define LOOM_REQUIRE_DATA(path_var, relative)                                   \
  const std::filesystem::path path_var = ::loom::test::data_file(relative);     \
  if (path_var.empty()) GTEST_SKIP() << "course data absent: " << (relative)

// A fresh, empty temporary folder for this test.
std::filesystem::path temp_dir();

// Runs the built `loom` command; returns its exit code, stdout+stderr in *output.
// Unless the arguments name a --cache folder, the run gets a fresh, empty
// persistent cache (XDG_CACHE_HOME in a new temporary folder).
int run_loom(const std::string& arguments, std::string* output = nullptr);
// run_loom with VAR=value assignments in front of the command.
int run_loom_env(const std::string& environment, const std::string& arguments, std::string* output = nullptr);
// Runs a shell script; returns its exit code, stdout+stderr in *output.
int run_shell(const std::string& script, std::string* output = nullptr);
// The environment assignment run_loom puts in front of the command.
std::string fresh_cache_env(const std::string& arguments);

}  // namespace loom::test
