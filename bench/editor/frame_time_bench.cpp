// Frame times of loom-editor on this machine's OpenGL (llvmpipe under Xvfb):
// a 200-node graph idle, while a long node runs, while a node is dragged
// during that run, and while a PoissonBlend region of 256x256 pixels is
// dragged over its target (with the blend updates per second).
//
//   tests/editor/run_under_xvfb.sh build/bin/bench_editor [--frames N]
//
// Wall time per frame depends on the machine's load; the UI thread's CPU time
// is the frame's own cost when llvmpipe rasterizes on that thread
// (LP_NUM_THREADS=0, which main() sets unless given).
//
// Writes bench/results/editor.csv (one row per phase) and editor_frames.csv
// with its plots (CPU and wall time per frame, by phase).
#include <GL/gl.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>

#include "bench_harness.hpp"
#include "ui/editor_app.hpp"

namespace {

using namespace loom::editor;
using loom::json;
using Clock = std::chrono::steady_clock;

double load_average() {
  double load[1] = {0};
  return getloadavg(load, 1) == 1 ? load[0] : -1;
}

// 200 nodes: a checkerboard and a long ImageWarp (3000x3000), and 198 Math
// nodes in 6 chains of 33.
json big_graph() {
  json nodes;
  nodes["board"] = {{"type", "Checkerboard"}, {"inputs", {{"size", {3000, 3000}}}}};
  nodes["warp"] = {{"type", "ImageWarp"},
                   {"inputs",
                    {{"image", {{"from", "board.image"}}},
                     {"method", "idw"},
                     {"pairs", {{0, 0, 10, 10}, {3000, 0, 3000, 0}, {0, 3000, 0, 3000}, {1500, 1500, 1600, 1400}}}}}};
  for (int chain = 0; chain < 6; ++chain)
    for (int i = 0; i < 33; ++i) {
      const std::string id = "m" + std::to_string(chain) + "_" + std::to_string(i);
      json inputs = {{"b", 1}};
      if (i > 0) inputs["a"] = {{"from", "m" + std::to_string(chain) + "_" + std::to_string(i - 1) + ".result"}};
      nodes[id] = {{"type", "Math"}, {"inputs", inputs}};
    }
  return {{"loom", 1}, {"nodes", nodes}};
}

json poisson_graph() {
  return json::parse(R"({"loom": 1, "nodes": {
    "target": {"type": "Checkerboard", "inputs": {"size": [640, 480], "cells": 4}},
    "source": {"type": "Checkerboard", "inputs": {"size": [300, 300], "cells": 10,
               "color_a": [0.95, 0.6, 0.2], "color_b": [0.1, 0.55, 0.5]}},
    "blend": {"type": "PoissonBlend", "inputs": {"source": {"from": "source.image"},
              "target": {"from": "target.image"}, "rectangle": [20, 20, 256, 256], "offset": [0, 0]}}}})");
}

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

struct Phase {
  std::string name;
  std::vector<double> ms;
  double updates_per_s = -1;
  std::vector<double> cpu_ms;  // the UI thread's CPU time per frame
  std::vector<FrameCost> costs;  // and where it went
};

struct Runner {
  Window window{"loom-editor bench", 1600, 900, false};
  EditorApp app;
  ScriptedInput input;
  explicit Runner(EditorOptions o) : app(std::move(o)) { window.set_profiling(true); }
  // Wall time of one frame; adds the UI thread's CPU time and its split to the phase.
  double frame(Phase* phase = nullptr) {
    const auto start = Clock::now();
    const double cpu_start = thread_cpu_ms();
    window.begin_frame(&input);
    app.draw(window);
    window.end_frame();
    glFinish();
    if (phase) {
      phase->cpu_ms.push_back(thread_cpu_ms() - cpu_start);
      phase->costs.push_back(window.last_cost());
    }
    return std::chrono::duration<double>(Clock::now() - start).count() * 1e3;
  }
  void settle() {
    while (!app.evaluation_current()) frame();
    frame();
  }
};


double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_editor",
                       "loom-editor frame times (run under Xvfb: "
                       "tests/editor/run_under_xvfb.sh build/bin/bench_editor).");
  int frames = 300;
  bool quick = false;
  cli.option("--frames", frames, "frames per phase (at least 10)").quick(quick, "60 frames per phase");
  cli.parse(argc, argv);
  frames = quick ? 60 : std::max(10, frames);
  setenv("LP_NUM_THREADS", "0", 0);  // before the GL context exists
  const auto dir = std::filesystem::temp_directory_path() / "loom-bench-editor";
  std::filesystem::create_directories(dir);
  EditorOptions options;
  options.config_dir = dir;
  options.output_dir = dir;
  std::vector<Phase> phases;
  const double load_start = load_average();
  {
    // The cost of the window itself: menus, panels, no graph.
    Runner r(options);
    r.input.mouse_x = 900;
    r.input.mouse_y = 880;
    Phase empty{"empty graph", {}, -1, {}, {}};
    for (int i = 0; i < frames; ++i) empty.ms.push_back(r.frame(&empty));
    phases.push_back(empty);
  }
  {
    Runner r(options);
    std::ofstream(dir / "big.json") << big_graph().dump();
    r.app.open(dir / "big.json");
    r.settle();
    GraphDocument& doc = r.app.document();
    r.input.mouse_x = 900;  // over the canvas, no node under it
    r.input.mouse_y = 880;

    Phase idle{"idle, 200 nodes", {}, -1, {}, {}};
    for (int i = 0; i < frames; ++i) idle.ms.push_back(r.frame(&idle));
    phases.push_back(idle);

    // Keep the long node running: restart it with a new power when it ends.
    int restarts = 0;
    auto keep_running = [&] {
      if (!r.app.controller().busy()) doc.set_input("warp", "idw_power", 2.0 + 0.01 * ++restarts);
    };
    Phase running{"long node running", {}, -1, {}, {}};
    for (int i = 0; i < frames; ++i) {
      keep_running();
      running.ms.push_back(r.frame(&running));
    }
    phases.push_back(running);

    Phase dragging{"dragging a node, long node running", {}, -1, {}, {}};
    const auto& state = r.app.state();
    const ImVec2 header = r.app.canvas().node_header(state, "m0_0");
    r.input.mouse_x = header.x;
    r.input.mouse_y = header.y;
    r.frame();
    r.input.mouse_down[0] = true;
    for (int i = 0; i < frames; ++i) {
      keep_running();
      r.input.mouse_x = header.x + 100 * std::sin(i * 0.05f);
      r.input.mouse_y = header.y + 60 * std::sin(i * 0.031f);
      dragging.ms.push_back(r.frame(&dragging));
    }
    r.input.mouse_down[0] = false;
    r.frame();
    phases.push_back(dragging);
    std::printf("long node restarted %d times; %zu nodes\n", restarts, doc.node_ids().size());
  }
  {
    Runner r(options);
    std::ofstream(dir / "poisson.json") << poisson_graph().dump();
    r.app.open(dir / "poisson.json");
    r.settle();
    const ImVec2 header = r.app.canvas().node_header(r.app.state(), "blend");
    r.input.mouse_x = header.x;
    r.input.mouse_y = header.y;
    r.frame();
    r.input.mouse_down[0] = true;
    r.frame();
    r.input.mouse_down[0] = false;
    r.settle();
    const ImageView view = r.app.image_view();
    if (view.scale <= 0) {
      std::fprintf(stderr, "bench_editor: the Poisson result is not shown\n");
      return 1;
    }
    Phase drag{"Poisson region 256x256 dragged", {}, -1, {}, {}};
    const ImVec2 start = view.to_screen(148, 148);
    r.input.mouse_x = start.x;
    r.input.mouse_y = start.y;
    r.frame();
    r.input.mouse_down[0] = true;
    std::set<std::uint64_t> shown;
    std::vector<double> solve_ms;  // PoissonBlend's run time per update shown
    const auto t0 = Clock::now();
    for (int i = 0; i < frames; ++i) {
      const float t = float(i) / float(frames);
      r.input.mouse_x = start.x + 300 * view.scale * t;
      r.input.mouse_y = start.y + 160 * view.scale * std::sin(6.28f * t);
      drag.ms.push_back(r.frame(&drag));
      if (const auto& e = r.app.state().eval; e && e->result.ok() && shown.insert(e->revision).second &&
                                              e->result.nodes.at("blend").status == loom::NodeStatus::ran)
        solve_ms.push_back(e->result.nodes.at("blend").seconds * 1e3);
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    r.input.mouse_down[0] = false;
    r.frame();
    drag.updates_per_s = double(shown.size()) / seconds;
    if (!solve_ms.empty())
      std::printf("Poisson drag: %zu new blends shown in %d frames, blend node median %.1f ms (wall, in the "
                  "editor's worker)\n",
                  shown.size(), frames, percentile(solve_ms, 0.5));
    phases.push_back(drag);
  }
  const double load_end = load_average();

  loom::bench::Csv summary("editor", {"phase", "frames", "median_ms", "p95_ms", "max_ms", "cpu_median_ms", "cpu_p95_ms",
                                      "blend_updates_per_s", "load_start", "load_end", "build_cpu_ms",
                                      "raster_cpu_ms", "swap_cpu_ms", "vertices", "draw_calls"});
  loom::bench::Csv per_frame("editor_frames", {"phase", "frame", "ms", "cpu_ms"});
  std::printf("%-40s %8s %8s | %8s %8s %8s | %8s %6s\n", "phase (medians)", "wall ms", "cpu ms", "build", "raster",
              "swap", "vertices", "draws");
  for (const Phase& p : phases) {
    auto median_of = [&](auto field) {
      std::vector<double> v;
      for (const FrameCost& c : p.costs) v.push_back(double(field(c)));
      return percentile(v, 0.5);
    };
    const double build = median_of([](const FrameCost& c) { return c.build_ms; });
    const double raster = median_of([](const FrameCost& c) { return c.raster_ms; });
    const double swap = median_of([](const FrameCost& c) { return c.swap_ms; });
    const double vertices = median_of([](const FrameCost& c) { return c.vertices; });
    const double draws = median_of([](const FrameCost& c) { return c.draw_calls; });
    std::printf("%-40s %8.1f %8.1f | %8.1f %8.1f %8.1f | %8.0f %6.0f\n", p.name.c_str(), percentile(p.ms, 0.5),
                percentile(p.cpu_ms, 0.5), build, raster, swap, vertices, draws);
    summary.row({p.name, (long long)p.ms.size(), percentile(p.ms, 0.5), percentile(p.ms, 0.95),
                 *std::max_element(p.ms.begin(), p.ms.end()), percentile(p.cpu_ms, 0.5),
                 percentile(p.cpu_ms, 0.95), p.updates_per_s, load_start, load_end, build, raster, swap,
                 (long long)vertices, (long long)draws});
    for (std::size_t i = 0; i < p.ms.size(); ++i) per_frame.row({p.name, (long long)i, p.ms[i], p.cpu_ms[i]});
  }
  summary.save();
  per_frame.save();
  loom::bench::PlotSpec spec;
  spec.x = "frame";
  spec.y = "cpu_ms";
  spec.group = "phase";
  spec.title = "loom-editor: UI thread CPU time per frame (llvmpipe on that thread, Xvfb)";
  loom::bench::plot(per_frame, spec);
  spec.y = "ms";
  spec.title = "loom-editor: wall time per frame (depends on the machine load)";
  spec.log_y = true;
  spec.file_suffix = "_wall";
  loom::bench::plot(per_frame, spec);
  return 0;
}
