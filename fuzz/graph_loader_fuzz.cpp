// libFuzzer target: graph text through parsing, --set and validation against
// the real registry (every plugin of this build). Any exception other than
// loom::Error, any crash, hang or sanitizer report is a finding.
//
// Input: a graph's JSON text; optionally followed by a line "\n--set " and an
// assignment ID.INPUT=VALUE applied before validation.
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>

#include "loom/graph.hpp"
#include "loom/plugin_loader.hpp"

namespace {

struct World {
  loom::Registry registry;
  loom::PluginLoader loader{registry};
  World() { loader.load_all(); }
};

World& world() {
  static World w;
  return w;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  World& w = world();
  std::string text(reinterpret_cast<const char*>(data), size);
  std::string assignment;
  if (auto at = text.find("\n--set "); at != std::string::npos) {
    assignment = text.substr(at + 7);
    text.resize(at);
  }
  try {
    loom::Graph g = loom::parse_graph_text(text, "fuzz.json");
    if (!assignment.empty()) loom::set_input(g, assignment);
    loom::validate_graph(g, w.registry, w.loader.searched_description());
    (void)loom::graph_to_json(g).dump();
  } catch (const loom::Error&) {
    // A clear error is the expected answer to bad input.
  }
  return 0;
}
