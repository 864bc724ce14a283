// What the persistent cache stores: reading back must beat computing again,
// per frame and over the frames of the run. The rule against cases worked by
// hand, then through the real `loom` command: a sequence of quick frames is
// served from disk on a rerun, and the frames finished before a Ctrl-C are
// reused by the next run.
#include <gtest/gtest.h>

#include "loom/disk_cache.hpp"
#include "runner_helpers.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;
using test::read_json;
using test::sequence_graph;
const auto loom = test::loom_with_test_plugins;

TEST(CacheRule, WeighsReadCostAgainstComputeCostPerFrameAndOverTheRun) {
  DiskCache::Options o;
  o.dir = test::temp_dir();
  o.min_seconds = 0.05;
  o.read_entry_seconds = 1e-3;
  o.read_mb_per_s = 100;  // 1 MB reads in 1 ms + 10 ms = 11 ms
  o.max_bytes = std::uint64_t(1) << 30;
  o.max_sequence_share = 0.25;  // 256 MB for a sequence
  const DiskCache cache(o);
  const std::uint64_t mb = 1 << 20;
  EXPECT_DOUBLE_EQ(cache.expected_read_seconds(mb), 0.011);
  // One evaluation: at least min_seconds, and a read at most half the compute.
  EXPECT_FALSE(cache.worth_storing(1000, 0.04));  // quick
  EXPECT_TRUE(cache.worth_storing(1000, 0.06));
  EXPECT_FALSE(cache.worth_storing(mb, 0.021));  // 11 ms to read back 21 ms of work
  EXPECT_TRUE(cache.worth_storing(mb, 0.05));
  // 60 frames of 30 ms: 1.8 s a run, each frame read back in 11 ms.
  EXPECT_TRUE(cache.worth_storing(mb, 0.03, 60));
  EXPECT_FALSE(cache.worth_storing(mb, 0.03, 1));  // one such frame alone: below min_seconds
  EXPECT_FALSE(cache.worth_storing(mb, 0.02, 60));  // 11 ms read > half of 20 ms
  EXPECT_FALSE(cache.worth_storing(100, 0.0005, 60));  // 30 ms over the run
  EXPECT_TRUE(cache.worth_storing(100, 0.005, 60));    // 0.3 s over the run, 1 ms reads
  // The sequence must fit in its share of the cache: 256 frames of 1 MB do, 257 do not.
  EXPECT_TRUE(cache.worth_storing(mb, 1.0, 256));
  EXPECT_FALSE(cache.worth_storing(mb, 1.0, 257));
}

TEST(CacheRule, ARerunOfASequenceOfQuickFramesReadsEveryFrameFromDisk) {
  const auto dir = test::temp_dir();
  std::ofstream(dir / "g.json") << sequence_graph(20, 10).dump(2);  // 10 ms a frame: below the floor alone
  const std::string common = "run " + (dir / "g.json").string() + " --cache " + (dir / "cache").string() +
                             " --out " + (dir / "out").string();
  const std::string run = common + " --profile " + (dir / "p.json").string();
  std::string out;
  ASSERT_EQ(loom(run, &out), 0) << out;
  EXPECT_EQ(read_json(dir / "p.json")["nodes"]["slow"]["runs"], 20);
  ASSERT_EQ(loom(run, &out), 0) << out;
  const json p = read_json(dir / "p.json");
  EXPECT_EQ(p["nodes"]["slow"]["runs"], 0) << p.dump(1);
  EXPECT_EQ(p["nodes"]["slow"]["disk_hits"], 20) << p.dump(1);
  // The same node in a one-frame run is below the floor: not stored.
  ASSERT_EQ(loom(common + " --frames 30 --profile " + (dir / "one.json").string(), &out), 0) << out;
  ASSERT_EQ(loom(common + " --frames 30 --profile " + (dir / "one.json").string(), &out), 0) << out;
  EXPECT_EQ(read_json(dir / "one.json")["nodes"]["slow"]["runs"], 1);
}

TEST(CacheRule, FramesFinishedBeforeAnInterruptAreReused) {
  const auto dir = test::temp_dir();
  // 30 ms a frame: each frame alone is below the 0.05 s floor, 80 of them are not.
  std::ofstream(dir / "g.json") << sequence_graph(80, 30).dump(2);
  const std::string run = "run " + (dir / "g.json").string() + " --cache " + (dir / "cache").string() +
                          " --out " + (dir / "out").string() + " --profile " + (dir / "p.json").string();
  std::string out;
  // Ctrl-C once some frames are written (at most 20 s).
  const int code = test::run_shell(
      "env LOOM_PLUGIN_PATH=" LOOM_TEST_PLUGIN_DIR " " LOOM_RUNNER " " + run + " & pid=$!; " +
          "for i in $(seq 200); do [ -e " + (dir / "out" / "x_4.txt").string() +
          " ] && break; sleep 0.05; done; kill -INT $pid; wait $pid",
      &out);
  ASSERT_EQ(code, 130) << out;
  int written = 0;
  for (int f = 1; f <= 80; ++f) written += fs::exists(dir / "out" / ("x_" + std::to_string(f) + ".txt"));
  ASSERT_GE(written, 4);
  ASSERT_LT(written, 80);
  ASSERT_EQ(loom(run, &out), 0) << out;
  const json p = read_json(dir / "p.json");
  // Every frame the first run wrote comes from disk (and the one whose Sleep
  // had finished when the interrupt came, if any); only the rest run.
  const int hits = p["nodes"]["slow"].value("disk_hits", 0);
  EXPECT_GE(hits, written) << p.dump(1);
  EXPECT_LE(hits, written + 1) << p.dump(1);
  EXPECT_EQ(p["nodes"]["slow"]["runs"].get<int>() + hits, 80) << p.dump(1);
}

}  // namespace
}  // namespace loom
