// loom-editor [GRAPH]: the visual node editor.
#include <cstdio>
#include <cstring>
#include <string>

#include "loom/process_start.hpp"
#include "ui/editor_app.hpp"

int main(int argc, char** argv) {
  loom::prepare_process(argv, /*evaluates_graphs=*/true);
  using namespace loom::editor;
  EditorOptions options;
  std::string graph;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::printf(
          "usage: loom-editor [GRAPH] [-o DIR] [--threads N]\n"
          "  GRAPH        a graph file to open (loom run reads the same files)\n"
          "  -o DIR       where Graph > Write outputs writes the sinks' files (default: .)\n"
          "  --threads N  evaluation threads (default: all cores)\n");
      return 0;
    } else if ((arg == "-o" || arg == "--output") && i + 1 < argc) {
      options.output_dir = argv[++i];
    } else if (arg == "--threads" && i + 1 < argc) {
      options.threads = std::atoi(argv[++i]);
    } else if (!arg.empty() && arg[0] == '-') {
      std::fprintf(stderr, "loom-editor: unknown option %s (see --help)\n", arg.c_str());
      return 2;
    } else {
      graph = arg;
    }
  }
  try {
    Window window("Loom editor", 1600, 900);
    EditorApp app(options);
    if (!graph.empty()) {
      try {
        app.open(graph);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "loom-editor: %s\n", e.what());
        return 2;
      }
    }
    while (!app.quit_requested()) {
      window.begin_frame();
      app.draw(window);
      window.end_frame();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loom-editor: %s\n", e.what());
    return 1;
  }
  return 0;
}
