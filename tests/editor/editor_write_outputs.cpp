// The editor's "Write outputs" without a window: GRAPH is loaded into the
// editor's document model and evaluated by its EvaluationController over the
// graph's time range, the sinks writing into OUT — the editor's column of the
// composition matrix (tests/composition/matrix_test.py), compared there with a
// plain `loom run` byte for byte. Exit 0 ok, 1 a node failed, 2 invalid graph.
#include <cstdio>
#include <filesystem>

#include "controller/evaluation_controller.hpp"
#include "loom/graph.hpp"
#include "loom/plugin_loader.hpp"
#include "model/graph_document.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: editor_write_outputs GRAPH OUT\n");
    return 2;
  }
  try {
    loom::Registry registry;
    loom::PluginLoader loader(registry);
    loader.load_all();
    loader.load_for(loom::node_types_used(loom::load_graph_file(argv[1])));  // types provided on demand (py.)
    loom::editor::GraphDocument doc(registry);
    doc.load(argv[1]);
    loom::editor::EvaluationController controller(registry);
    loom::editor::EvalRequest request;
    request.document = doc.evaluated_part();
    request.file = doc.file();
    request.output_dir = std::filesystem::absolute(argv[2]);
    request.revision = doc.revision();
    if (const auto range = doc.time_range()) request.frames = loom::FrameRange{range->start, range->end};
    controller.submit(std::move(request));
    controller.wait_idle();
    const auto e = controller.latest();
    if (!e) throw loom::Error("the evaluation did not finish");
    for (const auto& issue : e->issues) std::fprintf(stderr, "error: %s: %s\n", issue.pointer.c_str(), issue.message.c_str());
    if (!e->issues.empty()) return 2;
    if (!e->error.empty()) throw loom::Error(e->error);
    for (const auto& [id, report] : e->result.nodes)
      if (report.status == loom::NodeStatus::failed)
        std::fprintf(stderr, "error: node \"%s\" failed: %s\n", id.c_str(), report.error.c_str());
    return e->result.ok() ? 0 : 1;
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "error: %s\n", ex.what());
    return 1;
  }
}
