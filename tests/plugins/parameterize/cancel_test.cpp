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
#include "loom/testing.hpp"
#include "test_files.hpp"

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
                      EvalResult& r, int delay_ms = 50) {
  testing::Engine e;
  std::atomic<bool> cancel{false};
  CancelAfterStart observer(node, std::chrono::milliseconds(delay_ms), cancel);
  EvalOptions o;
  o.targets.push_back(parse_target(target));
  o.observer = &observer;
  o.cancel = &cancel;
  o.output_dir = out;
  r = e.session().evaluate(e.load(graph), o);
  const auto returned = Clock::now();
  observer.join();
  return std::chrono::duration<double>(returned - observer.set_at()).count();
}

// Nothing in the output folder: no file, no temporary file.
void expect_empty(const fs::path& dir) {
  for (const auto& entry : fs::recursive_directory_iterator(dir)) ADD_FAILURE() << "left behind: " << entry.path();
}

// The bound the issue asks for is ~0.5 s; the test allows 1 s on a loaded
// machine (2 cores shared) and prints the measured latency. One stage cannot
// be interrupted: the sparse factorization itself (UMFPACK for the default
// mean-value weights, ~2 s for these 499,000 unknowns at load ~2, 5 s at load
// 4); a flag that lands inside it acts right after it. Its latency is the
// factorization's own run time, which the machine's load decides, so that case
// is printed and checked for its outcome (cancelled, nothing written), not
// timed against a fixed bound.
constexpr double bound_seconds = 1.0;

TEST(ParameterizeCancel, MillionFaceSolveStopsWithinTheBound) {
  const fs::path out = test::temp_dir();
  const json g = {{"loom", 1},
                  {"nodes",
                   {{"dome", big_dome},
                    {"flat", {{"type", "Parameterize"}, {"inputs", {{"mesh", {{"from", "dome.mesh"}}}}}}},
                    {"save", {{"type", "SaveMesh"}, {"inputs", {{"mesh", {{"from", "flat.mesh"}}}, {"path", "flat.obj"}}}}}}}};
  // 50 ms lands in the weights; later flags land in assembly, the
  // factorization and the solves (the node takes ~1-2 s uncancelled).
  for (int delay_ms : {50, 300, 1100}) {
    EvalResult r;
    const double latency = cancel_latency(g, "flat", "save", out, r, delay_ms);
    if (!r.cancelled && r.nodes.at("flat").status != NodeStatus::failed) {
      std::printf("Parameterize finished before the flag at %d ms\n", delay_ms);
      continue;
    }
    std::printf("Parameterize (999,000 faces) cancelled %d ms after start: returned %.3f s after the flag\n",
                delay_ms, latency);
    EXPECT_TRUE(r.cancelled) << delay_ms;
    EXPECT_EQ(r.nodes.at("flat").error, "cancelled") << delay_ms;
    EXPECT_EQ(r.nodes.at("save").status, NodeStatus::skipped) << delay_ms;
    if (delay_ms < 500) {
      EXPECT_LT(latency, bound_seconds) << delay_ms;
    }
    expect_empty(out);
  }
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
    if (r.nodes.at("save").error.empty()) {  // the PLY bytes take ~50 ms: a race with the flag
      std::printf("SaveMesh %s finished before the flag (50 ms): nothing to cancel\n", file);
      continue;
    }
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
