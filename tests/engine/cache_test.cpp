// The persistent cache and frame sequences through the real `loom` command:
// hits across processes, corrupt and truncated entries recovered, concurrent
// runs on one cache, a rebuilt plugin missing, frame patterns, --frames,
// SaveVideo's frame count, and cancellation mid-sequence leaving no partial file.
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/videoio.hpp>

#include "loom/disk_cache.hpp"
#include "loom/scene.hpp"
#include "loom/testing.hpp"
#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

json graph(json nodes, json time = nullptr) {
  json g = {{"loom", 1}, {"nodes", std::move(nodes)}};
  if (!time.is_null()) g["time"] = std::move(time);
  return g;
}
json from(const std::string& link) { return {{"from", link}}; }

fs::path write_graph(const fs::path& dir, const json& doc, const std::string& name = "g.json") {
  std::ofstream(dir / name) << doc.dump(2);
  return dir / name;
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The runner with the test plugins on its path (in `plugins`, default the build's).
int loom(const std::string& args, std::string* out = nullptr, const std::string& plugins = LOOM_TEST_PLUGIN_DIR) {
  return test::run_loom_env("LOOM_PLUGIN_PATH=" + plugins, args, out);
}

std::vector<fs::path> entries(const fs::path& cache) {
  std::vector<fs::path> found;
  if (!fs::exists(cache)) return found;
  for (const auto& e : fs::recursive_directory_iterator(cache))
    if (e.is_regular_file() && e.path().extension() == ".loomcache") found.push_back(e.path());
  return found;
}

// A 150 ms node (stored: above the 50 ms threshold) feeding a file.
json slow_graph(double value) {
  return graph({{"slow", {{"type", "Sleep"}, {"inputs", {{"value", value}, {"ms", 150}}}}},
                {"fast", {{"type", "Math"}, {"inputs", {{"a", from("slow.value")}, {"b", 1}}}}},
                {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("fast.result")}, {"path", "x.txt"}}}}}});
}

TEST(DiskCache, ASecondProcessReadsTheSlowResultFromDisk) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, slow_graph(41));
  const std::string common = "run " + g.string() + " --cache " + (dir / "cache").string() + " --out " +
                             (dir / "out").string() + " --profile " + (dir / "p.json").string();
  std::string out;
  ASSERT_EQ(loom(common, &out), 0) << out;
  json p = read_json(dir / "p.json");
  EXPECT_EQ(p["nodes"]["slow"]["status"], "ran");
  EXPECT_EQ(entries(dir / "cache").size(), 1u);  // Math took microseconds: not stored
  EXPECT_EQ(read_text(dir / "out" / "x.txt"), "42.000000\n");
  fs::remove(dir / "out" / "x.txt");

  ASSERT_EQ(loom(common, &out), 0) << out;
  p = read_json(dir / "p.json");
  EXPECT_EQ(p["nodes"]["slow"]["status"], "cached");
  EXPECT_EQ(p["nodes"]["slow"]["source"], "disk");
  EXPECT_EQ(p["nodes"]["fast"]["status"], "ran");
  EXPECT_EQ(p["nodes"]["w"]["status"], "ran");
  EXPECT_GT(p["disk_cache"]["bytes_read"].get<double>(), 0);
  EXPECT_EQ(read_text(dir / "out" / "x.txt"), "42.000000\n");

  // --no-cache neither reads nor writes.
  ASSERT_EQ(loom(common + " --no-cache", &out), 0) << out;
  EXPECT_EQ(read_json(dir / "p.json")["nodes"]["slow"]["status"], "ran");
  // A changed input misses.
  ASSERT_EQ(loom(common + " --set slow.value=1", &out), 0) << out;
  EXPECT_EQ(read_json(dir / "p.json")["nodes"]["slow"]["status"], "ran");
  EXPECT_EQ(read_text(dir / "out" / "x.txt"), "2.000000\n");

  ASSERT_EQ(loom("cache info --cache " + (dir / "cache").string(), &out), 0) << out;
  EXPECT_NE(out.find("entries: 2"), std::string::npos) << out;
  ASSERT_EQ(loom("cache clear --cache " + (dir / "cache").string(), &out), 0) << out;
  EXPECT_TRUE(entries(dir / "cache").empty());
}

// Every file a result depends on is part of what decides its reuse, however
// its path arrived: literal, through a link, or named inside another file.
TEST(DiskCache, AChangedFileIsReadAgainWhetherItsPathIsLinkedOrNamedInAnotherFile) {
  auto dir = test::temp_dir();
  std::ofstream(dir / "number.txt") << "1\n";
  std::ofstream(dir / "list.txt") << "@number.txt\n";
  const json read = {{"type", "ReadNumber"}, {"inputs", {{"path", from("p.value")}, {"ms", 120}}}};
  for (const std::string named : {"number.txt", "list.txt"}) {
    auto g = write_graph(dir, graph({{"p", {{"type", "StringConstant"}, {"inputs", {{"value", named}}}}},
                                     {"r", read},
                                     {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("r.value")}, {"path", "x.txt"}}}}}}));
    const std::string common = "run " + g.string() + " --cache " + (dir / ("cache-" + named)).string() + " --out " +
                               (dir / "out").string() + " --profile " + (dir / "p.json").string();
    std::ofstream(dir / "number.txt") << "1\n";
    std::string out;
    ASSERT_EQ(loom(common, &out), 0) << out;
    EXPECT_EQ(read_text(dir / "out" / "x.txt"), "1.000000\n") << named;
    ASSERT_EQ(loom(common, &out), 0) << out;
    EXPECT_EQ(read_json(dir / "p.json")["nodes"]["r"]["source"], "disk") << named;
    std::ofstream(dir / "number.txt") << "22\n";  // another size: another stamp
    ASSERT_EQ(loom(common, &out), 0) << out;
    EXPECT_EQ(read_json(dir / "p.json")["nodes"]["r"]["status"], "ran") << named;
    EXPECT_EQ(read_text(dir / "out" / "x.txt"), "22.000000\n") << named;
  }
}

TEST(DiskCache, TheMemoryCacheOfASessionRereadsAChangedFileToo) {
  auto dir = test::temp_dir();
  std::ofstream(dir / "number.txt") << "5\n";
  std::ofstream(dir / "list.txt") << "@number.txt\n";
  testing::Engine e;
  Graph g = e.load(graph({{"p", {{"type", "StringConstant"}, {"inputs", {{"value", "list.txt"}}}}},
                          {"r", {{"type", "ReadNumber"}, {"inputs", {{"path", from("p.value")}}}}},
                          {"m", {{"type", "Math"}, {"inputs", {{"a", from("r.value")}, {"b", 1}}}}}}),
                   dir / "g.json");
  auto value = [&] { return e.run(g, {"m.result"}).output<double>("m.result"); };
  EXPECT_EQ(value(), 6);
  EXPECT_EQ(e.run(g, {"m.result"}).status("m"), NodeStatus::cached);
  std::ofstream(dir / "number.txt") << "70\n";
  EXPECT_EQ(value(), 71);  // m's own entry is stale too: it carries r's files
}

// LoadScene declares the files found inside its scene file: the .mtl that
// assimp opens and the textures the materials name. (A Scene is not stored on
// disk; a session's memory cache keeps the same stamps as a disk entry.)
TEST(DiskCache, ASceneIsReadAgainWhenItsMaterialLibraryOrATextureChanges) {
  auto dir = test::temp_dir();
  std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                     "vt 0 1\nusemtl m\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  std::ofstream(dir / "quad.mtl") << "newmtl m\nKd 0.8 0.2 0.2\n";
  std::ofstream(dir / "tex.ppm") << "P3\n1 1\n255\n10 20 30\n";
  testing::Engine e;
  Graph g = e.load(graph({{"s", {{"type", "LoadScene"}, {"inputs", {{"path", "quad.obj"}}}}}}), dir / "g.json");
  auto run = [&] {
    testing::Run r = e.run(g, {"s.scene"});
    EXPECT_TRUE(r.ok());
    return r;
  };
  auto material = [](const testing::Run& r) { return r.output<Scene>("s.scene").objects.at(0).material; };
  testing::Run first = run();
  EXPECT_EQ(first.status("s"), NodeStatus::ran);
  EXPECT_EQ(run().status("s"), NodeStatus::cached);
  std::ofstream(dir / "quad.mtl") << "newmtl m\nKd 0.2 0.8 0.2\n";  // same size, new colour
  fs::last_write_time(dir / "quad.mtl", fs::last_write_time(dir / "quad.mtl") + std::chrono::seconds(2));
  testing::Run recoloured = run();
  EXPECT_EQ(recoloured.status("s"), NodeStatus::ran);
  EXPECT_NEAR(material(first).base_color.x(), 0.8, 1e-6);
  EXPECT_NEAR(material(recoloured).base_color.x(), 0.2, 1e-6);
  std::ofstream(dir / "quad.mtl") << "newmtl m\nKd 0.2 0.8 0.2\nmap_Kd tex.ppm\n";
  testing::Run textured = run();
  EXPECT_EQ(textured.status("s"), NodeStatus::ran);
  EXPECT_EQ(run().status("s"), NodeStatus::cached);
  std::ofstream(dir / "tex.ppm") << "P3\n1 1\n255\n200 20 30\n";
  testing::Run retextured = run();
  EXPECT_EQ(retextured.status("s"), NodeStatus::ran);
  ASSERT_TRUE(material(textured).base_color_map && material(retextured).base_color_map);
  EXPECT_LT(material(textured).base_color_map->pixels.at<cv::Vec3f>(0, 0)[0],
            material(retextured).base_color_map->pixels.at<cv::Vec3f>(0, 0)[0]);
}

TEST(DiskCache, CorruptAndTruncatedEntriesAreDeletedRecomputedAndReported) {
  for (const char* damage : {"flip", "truncate", "empty"}) {
    auto dir = test::temp_dir();
    auto g = write_graph(dir, slow_graph(1));
    const std::string common = "run " + g.string() + " --cache " + (dir / "cache").string() + " --out " +
                               (dir / "out").string() + " --profile " + (dir / "p.json").string();
    std::string out;
    ASSERT_EQ(loom(common, &out), 0) << out;
    auto files = entries(dir / "cache");
    ASSERT_EQ(files.size(), 1u);
    const std::string bytes = read_text(files[0]);
    std::string bad = bytes;
    if (std::string(damage) == "flip") bad[bad.size() - 3] ^= 0x20;
    else if (std::string(damage) == "truncate") bad.resize(bad.size() - 5);
    else bad.clear();
    std::ofstream(files[0], std::ios::binary | std::ios::trunc) << bad;

    ASSERT_EQ(loom(common, &out), 0) << out;
    EXPECT_EQ(read_json(dir / "p.json")["nodes"]["slow"]["status"], "ran") << damage;
    EXPECT_NE(out.find("warning"), std::string::npos) << damage << ": " << out;
    EXPECT_NE(out.find("recomputing"), std::string::npos) << out;
    EXPECT_EQ(read_text(dir / "out" / "x.txt"), "2.000000\n");
    // Written again, whole: the same size, header (magic, version, key, count,
    // payload size) and values; only the compute time kept with them (and so
    // the payload's checksum) is this run's.
    const std::string again = read_text(files[0]);
    const std::size_t header = 8 + 4 + 8 + 4 + 8, checksum = 8, time = bytes.find("seconds");
    ASSERT_NE(time, std::string::npos);
    EXPECT_EQ(again.size(), bytes.size()) << damage;
    EXPECT_EQ(again.substr(0, header), bytes.substr(0, header)) << damage;
    EXPECT_EQ(again.substr(header + checksum, time - header - checksum),
              bytes.substr(header + checksum, time - header - checksum))
        << damage;
    ASSERT_EQ(loom(common, &out), 0) << out;
    EXPECT_EQ(read_json(dir / "p.json")["nodes"]["slow"]["source"], "disk") << damage;
  }
}

TEST(DiskCache, ConcurrentRunsOnOneCacheNeverCorruptIt) {
  auto dir = test::temp_dir();
  const fs::path cache = dir / "cache";
  // Six processes at once: three on the same graph (racing on the same
  // entries), three on others.
  std::string script;
  for (int i = 0; i < 6; ++i) {
    auto g = write_graph(dir, slow_graph(i < 3 ? 7 : 10 + i), "g" + std::to_string(i) + ".json");
    script += "env LOOM_PLUGIN_PATH=" LOOM_TEST_PLUGIN_DIR " " LOOM_RUNNER " run " + g.string() + " -q --cache " +
              cache.string() + " --out " + (dir / ("out" + std::to_string(i))).string() + " & ";
  }
  script += "fail=0; for j in $(jobs -p); do wait $j || fail=1; done; exit $fail";
  script = "bash -c '" + script + "'";  // dash's `jobs -p` lists nothing outside an interactive shell
  std::string out;
  ASSERT_EQ(test::run_shell(script, &out), 0) << out;
  EXPECT_EQ(entries(cache).size(), 4u);  // one per distinct value
  for (const auto& e : fs::recursive_directory_iterator(cache))
    if (e.is_regular_file() && e.path().filename() != "CACHEDIR.TAG") {
      EXPECT_EQ(e.path().extension(), ".loomcache") << "a temporary file was left: " << e.path();
    }
  for (int i = 0; i < 6; ++i) {
    auto g = dir / ("g" + std::to_string(i) + ".json");
    ASSERT_EQ(loom("run " + g.string() + " --cache " + cache.string() + " --out " + (dir / "again").string() +
                       " --profile " + (dir / "p.json").string(),
                   &out),
              0)
        << out;
    EXPECT_EQ(read_json(dir / "p.json")["nodes"]["slow"]["source"], "disk") << out;
    EXPECT_EQ(out.find("warning"), std::string::npos) << out;
    EXPECT_EQ(read_text(dir / "again" / "x.txt"), std::to_string((i < 3 ? 7 : 10 + i) + 1.0) + "\n");
  }
}

// Entries are keyed by the library's content identity (its GNU build ID, else
// its bytes), not its path or time: the same build installed elsewhere shares
// them, another build never does. `objcopy --remove-section` makes "another
// build" from a copy (its identity falls back to the bytes, which differ).
TEST(DiskCache, EntriesFollowTheBuildsContentNotItsPathOrTime) {
  if (std::system("command -v objcopy > /dev/null 2>&1") != 0) GTEST_SKIP() << "objcopy (binutils) not found";
  auto dir = test::temp_dir();
  auto g = write_graph(dir, slow_graph(3));
  const std::string common = "run " + g.string() + " --cache " + (dir / "cache").string() + " --out " +
                             (dir / "out").string() + " --profile " + (dir / "p.json").string();
  auto slow_status = [&](const fs::path& plugins) {
    std::string out;
    EXPECT_EQ(loom(common, &out, plugins.string()), 0) << out;
    const json p = read_json(dir / "p.json");
    return p["nodes"]["slow"].value("source", p["nodes"]["slow"]["status"].get<std::string>());
  };
  auto install = [&](const fs::path& from, const fs::path& to) {  // another path, a later time
    fs::copy(from, to, fs::copy_options::recursive);
    for (const auto& e : fs::directory_iterator(to))
      if (e.path().extension() == ".so")
        fs::last_write_time(e.path(), fs::last_write_time(e.path()) + std::chrono::seconds(5));
  };
  install(LOOM_TEST_PLUGIN_DIR, dir / "a");
  EXPECT_EQ(slow_status(dir / "a"), "ran");
  EXPECT_EQ(slow_status(dir / "a"), "disk");
  install(dir / "a", dir / "b");
  EXPECT_EQ(slow_status(dir / "b"), "disk");  // the same build elsewhere: shared
  for (const auto& e : fs::directory_iterator(dir / "b")) {
    if (e.path().extension() != ".so") continue;
    ASSERT_EQ(std::system(("objcopy --remove-section .note.gnu.build-id " + e.path().string()).c_str()), 0);
  }
  EXPECT_EQ(slow_status(dir / "b"), "ran");  // another build: never the old results
  install(dir / "b", dir / "c");
  EXPECT_EQ(slow_status(dir / "c"), "disk");  // no build ID: the same bytes are the same build
}

TEST(DiskCache, LeastRecentlyUsedEntriesGoFirstUnderTheSizeLimit) {
  auto dir = test::temp_dir();
  DiskCache::Options o;
  o.dir = dir;
  DiskCache cache(o);
  const Value big = Value::make(std::vector<double>(100000, 1.0));  // ~800 kB an entry
  for (std::uint64_t k = 1; k <= 4; ++k) {
    ASSERT_GT(cache.store(k, {big}), 800000u);
    for (const auto& e : entries(dir))  // distinct access times, oldest first
      fs::last_write_time(e, fs::last_write_time(e) - std::chrono::seconds(10));
  }
  ASSERT_TRUE(cache.load(1));  // key 1 becomes the most recently used
  o.max_bytes = 2500000;       // room for three
  DiskCache limited(o);
  limited.trim();
  EXPECT_TRUE(limited.contains(1));
  EXPECT_FALSE(limited.contains(2));
  EXPECT_TRUE(limited.contains(3));
  EXPECT_TRUE(limited.contains(4));
  // Too quick to compute, or slower to read back than to compute: not stored.
  EXPECT_EQ(cache.store(10, {Value::make(1.0)}, 0.01), 0u);
  EXPECT_GT(cache.store(11, {Value::make(1.0)}, 0.06), 0u);
  const Value huge = Value::make(std::vector<double>(2 * 1024 * 1024, 1.0));  // 16 MB: ~55 ms to read
  EXPECT_EQ(cache.store(12, {huge}, 0.1), 0u);
  EXPECT_GT(cache.store(13, {huge}, 5.0), 0u);
  // A type that cannot be serialized is simply not stored.
  EXPECT_EQ(cache.store(9, {Value::make(Any{})}), 0u);
  EXPECT_FALSE(cache.contains(9));
}

TEST(DiskCache, SimulationStatesOutliveTheProcessAndADownstreamChangeDoesNotReSimulate) {
  auto dir = test::temp_dir();
  // Each step sleeps 60 ms: every state is worth storing.
  auto g = write_graph(dir, graph({{"sim", {{"type", "Integrate"}, {"inputs", {{"x", 0.0}, {"v", 2.4}, {"ms", 60}}}}},
                                   {"out", {{"type", "Math"}, {"inputs", {{"a", from("sim.x")}, {"b", 1}}}}},
                                   {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("out.result")}, {"path", "x_{frame}.txt"}}}}}},
                                  {{"start", 1}, {"end", 6}, {"fps", 24}}));
  const std::string common = "run " + g.string() + " --cache " + (dir / "cache").string() + " --out " +
                             (dir / "out").string() + " --profile " + (dir / "p.json").string();
  std::string out;
  ASSERT_EQ(loom(common + " --frames 1-4", &out), 0) << out;
  EXPECT_EQ(read_json(dir / "p.json")["nodes"]["sim"]["runs"], 4);
  // A new process asked for frame 6 steps on from the stored frame 4.
  ASSERT_EQ(loom(common + " --frames 6", &out), 0) << out;
  json p = read_json(dir / "p.json");
  EXPECT_EQ(p["nodes"]["sim"]["runs"], 2) << p.dump();
  EXPECT_DOUBLE_EQ(std::stod(read_text(dir / "out" / "x_6.txt")), 1 + 5 * 2.4 / 24);
  // Downstream only: every frame from disk, no step.
  ASSERT_EQ(loom(common + " --set out.b=100", &out), 0) << out;
  p = read_json(dir / "p.json");
  EXPECT_EQ(p["nodes"]["sim"]["runs"], 0) << p.dump();
  EXPECT_EQ(p["nodes"]["sim"]["source"], "disk");
  EXPECT_EQ(p["nodes"]["out"]["runs"], 6);
  EXPECT_DOUBLE_EQ(std::stod(read_text(dir / "out" / "x_6.txt")), 100 + 5 * 2.4 / 24);
  // A parameter of the simulation: every frame again.
  ASSERT_EQ(loom(common + " --set sim.v=1", &out), 0) << out;
  EXPECT_EQ(read_json(dir / "p.json")["nodes"]["sim"]["runs"], 6);
}

TEST(Sequences, FramePatternsWriteOneFilePerFrameAndDashDashFramesOverridesTheRange) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"f", {{"type", "FrameNumber"}, {"inputs", {{"scale", 10}}}}},
                                   {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("f.value")}, {"path", "t/f_{frame:03}.txt"}}}}}},
                                  {{"start", 1}, {"end", 4}, {"fps", 24}}));
  std::string out;
  ASSERT_EQ(loom("run " + g.string() + " --out " + (dir / "a").string(), &out), 0) << out;
  for (int f = 1; f <= 4; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "f_%03d.txt", f);
    EXPECT_EQ(read_text(dir / "a" / "t" / name), std::to_string(10.0 * f) + "\n") << name;
  }
  EXPECT_NE(out.find("over 4 frames"), std::string::npos) << out;
  ASSERT_EQ(loom("run " + g.string() + " --frames 7-8 --out " + (dir / "b").string(), &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir / "b" / "t" / "f_007.txt"));
  EXPECT_TRUE(fs::exists(dir / "b" / "t" / "f_008.txt"));
  EXPECT_FALSE(fs::exists(dir / "b" / "t" / "f_001.txt"));
  ASSERT_EQ(loom("run " + g.string() + " --frames 3 --set time.start=3 --out " + (dir / "c").string(), &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir / "c" / "t" / "f_003.txt"));
  EXPECT_EQ(loom("run " + g.string() + " --frames 5-2", &out), 2) << out;
  EXPECT_EQ(loom("run " + g.string() + " --frames x", &out), 2) << out;
  EXPECT_EQ(loom("run " + g.string() + " --set time.end=0", &out), 2) << out;
}

TEST(Sequences, SaveVideoWritesEveryFrameInOrderAsOneMp4) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {96, 64}}, {"cells", 4}}}}},
                                   {"video", {{"type", "SaveVideo"}, {"inputs", {{"image", from("board.image")}, {"path", "v/out.mp4"}}}}}},
                                  {{"start", 1}, {"end", 12}, {"fps", 24}}));
  std::string out;
  ASSERT_EQ(loom("run " + g.string() + " --out " + (dir / "o").string(), &out, LOOM_PLUGIN_DIR), 0) << out;
  EXPECT_NE(out.find("12 frames"), std::string::npos) << out;
  std::printf("SaveVideo here: %s\n", out.substr(out.find("12 frames")).c_str());
  cv::VideoCapture video((dir / "o" / "v" / "out.mp4").string(), cv::CAP_FFMPEG);
  ASSERT_TRUE(video.isOpened());
  EXPECT_EQ(video.get(cv::CAP_PROP_FRAME_WIDTH), 96);
  EXPECT_EQ(video.get(cv::CAP_PROP_FRAME_HEIGHT), 64);
  int frames = 0;
  cv::Mat frame;
  while (video.read(frame)) ++frames;
  EXPECT_EQ(frames, 12);
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "o")) files += e.is_regular_file();
  EXPECT_EQ(files, 1);  // no temporary left
}

TEST(Sequences, CancellingMidSequenceLeavesNoPartialFile) {
  auto dir = test::temp_dir();
  auto g = write_graph(dir, graph({{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {64, 64}}}}}},
                                   {"video", {{"type", "SaveVideo"}, {"inputs", {{"image", from("board.image")}, {"path", "out.mp4"}}}}},
                                   {"f", {{"type", "FrameNumber"}}},
                                   {"slow", {{"type", "Sleep"}, {"inputs", {{"value", from("f.value")}, {"ms", 200}}}}},
                                   {"w", {{"type", "WriteText"}, {"inputs", {{"value", from("slow.value")}, {"path", "t_{frame}.txt"}}}}}},
                                  {{"start", 1}, {"end", 50}, {"fps", 24}}));
  std::string out;
  const std::string path = std::string(LOOM_PLUGIN_DIR) + ":" + LOOM_TEST_PLUGIN_DIR;
  int code = test::run_shell("env LOOM_PLUGIN_PATH=" + path + " " + test::fresh_cache_env("") + LOOM_RUNNER +
                                 " run " + g.string() + " --out " + (dir / "out").string() +
                                 " & pid=$!; while [ ! -e " + (dir / "out" / "t_2.txt").string() +
                                 " ]; do sleep 0.05; done; kill -INT $pid; wait $pid",
                             &out);
  EXPECT_EQ(code, 130) << out;
  EXPECT_FALSE(fs::exists(dir / "out" / "out.mp4"));
  int texts = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "out")) {
    ASSERT_EQ(e.path().extension(), ".txt") << "left behind: " << e.path();
    const int frame = std::stoi(e.path().stem().string().substr(2));
    EXPECT_EQ(read_text(e.path()), std::to_string(static_cast<double>(frame)) + "\n");  // whole files only
    ++texts;
  }
  EXPECT_GE(texts, 1);
  EXPECT_LT(texts, 50);
}

}  // namespace
}  // namespace loom
