// Ctrl-C during the long work: a cancel flag set from another thread while a
// ~1M-face Parameterize solves, or while SaveMesh formats a ~1M-face mesh,
// ends the evaluation within a bound and writes nothing.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "loom/evaluator.hpp"
#include "loom_test.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Sets the cancel flag `delay` after the node `id` starts and records when.
class CancelAfterStart : public Observer {
 public:
  CancelAfterStart(std::string id, std::chrono::milliseconds delay, std::atomic<bool>& cancel)
      : id_(std::move(id)), delay_(delay), cancel_(cancel) {}
  ~CancelAfterStart() override {
    if (thread_.joinable()) thread_.join();
  }
  void node_started(const std::string& id, const std::string&) override {
    if (id != id_ || thread_.joinable()) return;
    thread_ = std::thread([this] {
      std::this_thread::sleep_for(delay_);
      set_at_ = Clock::now();
      cancel_ = true;
    });
  }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  Clock::time_point set_at() const { return set_at_; }

 private:
  std::string id_;
  std::chrono::milliseconds delay_;
  std::atomic<bool>& cancel_;
  std::thread thread_;
  Clock::time_point set_at_{};
};

// 500 rings of 1000 segments: 999,000 triangles, 500,001 vertices.
const json big_dome = {{"type", "HemisphereMesh"}, {"inputs", {{"rings", 500}, {"segments", 1000}}}};

// Runs the graph, cancelling 50 ms after `node` starts; returns the seconds
// from the flag to the evaluation's return.
double cancel_latency(const json& graph, const std::string& node, const std::string& target, const fs::path& out,
                      EvalResult& r) {
  test::Engine e;
  std::atomic<bool> cancel{false};
  CancelAfterStart observer(node, std::chrono::milliseconds(50), cancel);
  EvalOptions o;
  o.targets.push_back(parse_target(target));
  o.observer = &observer;
  o.cancel = &cancel;
  o.output_dir = out;
  r = e.session.evaluate(e.graph(graph), o);
  const auto returned = Clock::now();
  observer.join();
  EXPECT_TRUE(cancel) << "the node finished before the flag was set: the load is too small";
  return std::chrono::duration<double>(returned - observer.set_at()).count();
}

// Nothing in the output folder: no file, no temporary file.
void expect_empty(const fs::path& dir) {
  for (const auto& entry : fs::recursive_directory_iterator(dir)) ADD_FAILURE() << "left behind: " << entry.path();
}

// The bound the issue asks for is ~0.5 s; the test allows 1 s on a loaded
// machine (2 cores shared) and prints the measured latency.
constexpr double bound_seconds = 1.0;

TEST(ParameterizeCancel, MillionFaceSolveStopsWithinTheBound) {
  const fs::path out = test::temp_dir();
  const json g = {{"loom", 1},
                  {"nodes",
                   {{"dome", big_dome},
                    {"flat", {{"type", "Parameterize"}, {"inputs", {{"mesh", {{"from", "dome.mesh"}}}}}}},
                    {"save", {{"type", "SaveMesh"}, {"inputs", {{"mesh", {{"from", "flat.mesh"}}}, {"path", "flat.obj"}}}}}}}};
  EvalResult r;
  const double latency = cancel_latency(g, "flat", "save", out, r);
  std::printf("Parameterize (999,000 faces) cancelled 50 ms after start: returned %.3f s after the flag\n", latency);
  EXPECT_TRUE(r.cancelled);
  EXPECT_EQ(r.nodes.at("flat").error, "cancelled");
  EXPECT_EQ(r.nodes.at("save").status, NodeStatus::skipped);
  EXPECT_LT(latency, bound_seconds);
  expect_empty(out);
}

TEST(ParameterizeCancel, MillionFaceSaveMeshStopsWithinTheBoundAndWritesNothing) {
  for (const char* file : {"dome.obj", "dome.ply"}) {
    const fs::path out = test::temp_dir();
    const json g = {{"loom", 1},
                    {"nodes",
                     {{"dome", big_dome},
                      {"save", {{"type", "SaveMesh"}, {"inputs", {{"mesh", {{"from", "dome.mesh"}}}, {"path", file}}}}}}}};
    EvalResult r;
    const double latency = cancel_latency(g, "save", "save", out, r);
    std::printf("SaveMesh %s (999,000 faces) cancelled 50 ms after start: returned %.3f s after the flag\n", file,
                latency);
    EXPECT_TRUE(r.cancelled) << file;
    EXPECT_EQ(r.nodes.at("save").error, "cancelled") << file;
    EXPECT_LT(latency, bound_seconds) << file;
    expect_empty(out);
  }
}

}  // namespace
}  // namespace loom
