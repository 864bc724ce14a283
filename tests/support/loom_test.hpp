// Helpers for tests that run nodes through the real engine: the plugins are
// loaded from the build, graphs are JSON written in the test.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "loom/evaluator.hpp"
#include "loom/plugin_loader.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

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

}  // namespace loom::test
