// What `loom` says to a user who makes the usual mistakes, and how it reports
// while it works: a mistyped command, a missing input file, progress written to
// a log (not a terminal), and `loom run --watch`.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "runner_helpers.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;
using test::from;
using test::read_text;
using test::sequence_graph;
using test::write_graph;
const auto loom = test::loom_with_test_plugins;

std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> found;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) found.push_back(line);
  return found;
}

TEST(RunnerMessages, AnUnknownCommandIsNamedWithTheNearestOne) {
  std::string out;
  EXPECT_EQ(test::run_loom("rnu graphs/demo.json", &out), 2);
  EXPECT_NE(out.find("unknown command \"rnu\": did you mean \"run\"?"), std::string::npos) << out;
  EXPECT_EQ(out.find("A subcommand is required"), std::string::npos) << out;
  EXPECT_EQ(test::run_loom("vaildate g.json", &out), 2);
  EXPECT_NE(out.find("did you mean \"validate\"?"), std::string::npos) << out;
  // Nothing near: named, with the list of commands.
  EXPECT_EQ(test::run_loom("frobnicate", &out), 2);
  EXPECT_NE(out.find("unknown command \"frobnicate\" (commands: run,"), std::string::npos) << out;
  // Options and real commands are CLI11's as before.
  EXPECT_EQ(test::run_loom("--help", &out), 0) << out;
  EXPECT_EQ(test::run_loom("nodes Math", &out), 0) << out;
}

// CLI11 hands an option that needs a value the next word, whatever it is: before
// this rule `--profile --quiet` wrote the profile to a file named "--quiet" and
// ran without --quiet. Now such a command is refused, naming both, and writes
// nothing; a value after its option, and sbatch's options given to --slurm-arg
// (not loom's own), go through as before.
TEST(RunnerMessages, AnOptionGivenAsAnothersValueIsRefusedNamingBoth) {
  const auto dir = test::temp_dir();
  const auto g = write_graph(dir, sequence_graph(1, 0));
  const std::string run = "run " + g.string() + " --no-cache --out " + (dir / "out").string();
  std::string out;
  EXPECT_EQ(loom(run + " --profile --quiet", &out), 2);
  EXPECT_NE(out.find("--profile: needs a value before \"--quiet\", which is an option (write: --profile VALUE "
                     "--quiet)"),
            std::string::npos)
      << out;
  EXPECT_EQ(loom(run + " --profile -q", &out), 2);
  EXPECT_NE(out.find("needs a value before \"-q\""), std::string::npos) << out;
  EXPECT_EQ(loom(run + " --profile --frames=1", &out), 2);
  EXPECT_NE(out.find("needs a value before \"--frames=1\""), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "out")) << "nothing runs";
  EXPECT_EQ(loom("submit " + g.string() + " --to local --job-dir --chunk=2", &out), 2);
  EXPECT_NE(out.find("--job-dir: needs a value before \"--chunk=2\""), std::string::npos) << out;
  // As meant: the value first.
  ASSERT_EQ(loom(run + " --profile " + (dir / "p.json").string() + " --quiet", &out), 0) << out;
  EXPECT_TRUE(fs::exists(dir / "p.json"));
  EXPECT_TRUE(out.empty()) << out;  // --quiet applied
  ASSERT_EQ(
      loom("submit " + g.string() + " --to local --slurm-arg=--partition=gpu --out " + (dir / "job").string(), &out), 0)
      << out;
}

// Numbers out of range are said in words, where CLI11 said "Value 0 not in
// range 0.000000 to 17976931348623157081..." (for a positive number, 0 too).
TEST(RunnerMessages, ANumberOutOfRangeIsSaidInWords) {
  const auto dir = test::temp_dir();
  const auto g = write_graph(dir, sequence_graph(1, 0));
  const std::string run = "run " + g.string() + " --no-cache --out " + (dir / "out").string();
  std::string out;
  const auto refused = [&](const std::string& args, const std::string& message) {
    EXPECT_EQ(loom(args, &out), 2) << args;
    EXPECT_NE(out.find(message), std::string::npos) << args << "\n" << out;
    EXPECT_EQ(out.find("not in range"), std::string::npos) << out;
  };
  refused(run + " --threads -1", "--threads: expected a whole number of at least 0, got \"-1\"");
  refused(run + " --threads 1.5", "--threads: expected a whole number of at least 0, got \"1.5\"");
  refused(run + " --threads two", "--threads: expected a whole number of at least 0, got \"two\"");
  refused(run + " --cache-limit 0", "--cache-limit: expected a number above 0, got \"0\"");
  refused(run + " --preview-every -1", "--preview-every: expected a number of at least 0, got \"-1\"");
  refused("submit " + g.string() + " --to local -j 0", "--jobs: expected a whole number of at least 1, got \"0\"");
  refused("submit " + g.string() + " --to local --cache-limit -5",
          "--cache-limit: expected a number above 0, got \"-5\"");
  EXPECT_FALSE(fs::exists(dir / "out"));
  // In range, as before: a small cache limit, all cores.
  EXPECT_EQ(loom(run + " --threads 0 --cache-limit 0.005 --preview-every 0", &out), 0) << out;
}

TEST(RunnerMessages, AMissingInputFileSuggestsTheClosestNameAndSaysHowItWasResolved) {
  const auto dir = test::temp_dir();
  fs::create_directories(dir / "meshes");
  std::ofstream(dir / "meshes" / "Balls.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir / "meshes" / "cube.obj") << "v 0 0 0\n";
  auto run_with = [&](const std::string& path, std::string* out) {
    const auto g = write_graph(dir, {{"loom", 1},
                                     {"nodes",
                                      {{"m", {{"type", "LoadMesh"}, {"inputs", {{"path", path}}}}},
                                       {"s", {{"type", "SaveMesh"},
                                              {"inputs", {{"mesh", from("m.mesh")}, {"path", "o.obj"}}}}}}}});
    return test::run_loom("run " + g.string() + " --no-cache --out " + (dir / "out").string(), out);
  };
  std::string out;
  EXPECT_EQ(run_with("meshes/balls.obj", &out), 1);
  const std::string folder = dir.lexically_normal().string();
  EXPECT_NE(out.find("cannot read mesh " + folder + "/meshes/balls.obj: no such file; did you mean \"Balls.obj\"? "
                     "(a relative path is resolved against the graph file's folder, " + folder + ")"),
            std::string::npos)
      << out;
  EXPECT_EQ(out.find("cube.obj"), std::string::npos) << out;  // not near
  // A mistyped folder is named as the folder.
  EXPECT_EQ(run_with("mehses/Balls.obj", &out), 1);
  EXPECT_NE(out.find("no such folder " + folder + "/mehses; did you mean \"meshes\"?"), std::string::npos) << out;
  // The name as it is: the mesh loads.
  EXPECT_EQ(run_with("meshes/Balls.obj", &out), 0) << out;
}

TEST(RunnerMessages, WithoutATerminalProgressIsOneLinePerFrame) {
  const auto dir = test::temp_dir();
  const auto g = write_graph(dir, sequence_graph(5, 400));
  std::string out;  // run_loom reads stderr through a pipe: not a terminal
  ASSERT_EQ(loom("run " + g.string() + " --no-cache --out " + (dir / "out").string(), &out), 0) << out;
  EXPECT_EQ(lines_starting(out, "frame "),
            (std::vector<std::string>{"frame 1 of 5", "frame 2 of 5", "frame 3 of 5", "frame 4 of 5", "frame 5 of 5"}))
      << out;
  EXPECT_EQ(out.find('%'), std::string::npos) << out;  // no percentages within a frame
  EXPECT_EQ(out.find("done in"), std::string::npos) << out;
  // Another range: the frame, then its place in the run.
  ASSERT_EQ(loom("run " + g.string() + " --no-cache --frames 3-4 --out " + (dir / "out").string(), &out), 0) << out;
  EXPECT_EQ(lines_starting(out, "frame "), (std::vector<std::string>{"frame 3 (1 of 2)", "frame 4 (2 of 2)"})) << out;
  // One evaluation of a slow node still says how far it is.
  const auto single = write_graph(dir,
                                  {{"loom", 1},
                                   {"nodes",
                                    {{"slow", {{"type", "Sleep"}, {"inputs", {{"ms", 400}}}}},
                                     {"w", {{"type", "WriteText"},
                                            {"inputs", {{"value", from("slow.value")}, {"path", "y.txt"}}}}}}}},
                                  "single.json");
  ASSERT_EQ(loom("run " + single.string() + " --no-cache --out " + (dir / "out").string(), &out), 0) << out;
  EXPECT_NE(out.find("[slow] 50%"), std::string::npos) << out;
  EXPECT_TRUE(lines_starting(out, "frame ").empty()) << out;
}

// Runs `loom run --watch` in the background; `then` changes files while it
// watches; Ctrl-C ends it. Returns its exit code and output.
int watch_while(const fs::path& graph, const fs::path& out_dir, const std::string& then, std::string* out) {
  const fs::path log = graph.parent_path() / "watch.log";
  const std::string script = "env LOOM_PLUGIN_PATH=" LOOM_TEST_PLUGIN_DIR " " LOOM_RUNNER " run " + graph.string() +
                             " --no-cache --watch --out " + out_dir.string() + " > " + log.string() +
                             " 2>&1 & pid=$!; " + then + "; kill -INT $pid; wait $pid";
  const int code = test::run_shell(script, out);
  *out += read_text(log);
  return code;
}

// Waits until `file` holds `text` (at most 20 s): the watcher has run again.
std::string wait_for(const fs::path& file, const std::string& text) {
  return "for i in $(seq 200); do grep -qx '" + text + "' " + file.string() + " 2>/dev/null && break; sleep 0.1; done";
}

TEST(RunnerMessages, WatchRunsAgainWhenTheGraphOrAnInputFileChanges) {
  const auto dir = test::temp_dir();
  // An input file the graph reads: a mesh whose vertex count is written out.
  std::ofstream(dir / "in.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const json doc = {{"loom", 1},
                    {"nodes",
                     {{"m", {{"type", "LoadMesh"}, {"inputs", {{"path", "in.obj"}}}}},
                      {"s", {{"type", "SaveMesh"}, {"inputs", {{"mesh", from("m.mesh")}, {"path", "o.obj"}}}}},
                      {"w", {{"type", "WriteText"}, {"inputs", {{"value", 7}, {"path", "n.txt"}}}}}}}};
  const auto g = write_graph(dir, doc);
  const fs::path out_dir = dir / "out";
  json edited = doc;
  edited["nodes"]["w"]["inputs"]["value"] = 8;
  const fs::path edited_file = dir / "edited.json";
  std::ofstream(edited_file) << edited.dump(2);
  // 1. the first run; 2. the input mesh replaced by renaming a new file onto it
  // (as editors save); 3. the graph edited in place.
  const std::string then =
      wait_for(out_dir / "n.txt", "7.000000") + "; " +
      "printf 'v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nv 1 1 0\\nf 1 2 3\\nf 2 4 3\\n' > " + (dir / "new.obj").string() +
      "; mv " + (dir / "new.obj").string() + " " + (dir / "in.obj").string() + "; " +
      "for i in $(seq 200); do grep -c '^v ' " + (out_dir / "o.obj").string() +
      " 2>/dev/null | grep -qx 4 && break; sleep 0.1; done; " + "cat " + edited_file.string() + " > " + g.string() +
      "; " + wait_for(out_dir / "n.txt", "8.000000");
  std::string out;
  EXPECT_EQ(watch_while(g, out_dir, then, &out), 0) << out;
  EXPECT_NE(out.find("changed: " + (dir / "in.obj").string() + ": running again"), std::string::npos) << out;
  EXPECT_NE(out.find("changed: " + g.string() + ": running again"), std::string::npos) << out;
  EXPECT_EQ(lines_starting(out, "watching 2 files for changes (Ctrl-C to stop)").size(), 3u) << out;
  EXPECT_EQ(read_text(out_dir / "n.txt"), "8.000000\n");
  std::ifstream mesh(out_dir / "o.obj");
  int vertices = 0;
  for (std::string line; std::getline(mesh, line);) vertices += line.rfind("v ", 0) == 0;
  EXPECT_EQ(vertices, 4);
}

TEST(RunnerMessages, WatchKeepsWatchingAfterABrokenEdit) {
  const auto dir = test::temp_dir();
  const json doc = {{"loom", 1},
                    {"nodes", {{"w", {{"type", "WriteText"}, {"inputs", {{"value", 1}, {"path", "n.txt"}}}}}}}};
  const auto g = write_graph(dir, doc);
  json fixed = doc;
  fixed["nodes"]["w"]["inputs"]["value"] = 2;
  std::ofstream(dir / "fixed.json") << fixed.dump(2);
  const fs::path out_dir = dir / "out";
  const std::string then = wait_for(out_dir / "n.txt", "1.000000") + "; echo '{\"loom\": 1, \"nodes\": ' > " +
                           g.string() + "; sleep 2; cat " + (dir / "fixed.json").string() + " > " + g.string() +
                           "; " + wait_for(out_dir / "n.txt", "2.000000");
  std::string out;
  EXPECT_EQ(watch_while(g, out_dir, then, &out), 0) << out;
  EXPECT_NE(out.find("error: " + g.string()), std::string::npos) << out;  // the broken file is reported
  EXPECT_EQ(read_text(out_dir / "n.txt"), "2.000000\n");                  // and the fixed one runs
}

}  // namespace
}  // namespace loom
