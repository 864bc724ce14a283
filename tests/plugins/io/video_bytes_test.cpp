// SaveVideo writes the same MP4 bytes whatever cores the process may run on
// and whatever --threads says: the same graph under `taskset -c 0` and
// `taskset -c 0,1`, with 1 and 2 worker threads. (x264's default thread
// count follows the CPUs a process sees, and its output follows its thread
// count: mpirun's core binding changed the bytes of a video.)
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(VideoFiles, SameBytesWhateverTheCoresAndThreads) {
  if (test::run_shell("taskset -c 0,1 true") != 0) GTEST_SKIP() << "needs taskset and two cores to bind to";
  const fs::path dir = test::temp_dir();
  const std::string graph = std::string(LOOM_SOURCE_DIR) + "/graphs/time-twist-sequence.json";
  struct Run {
    const char* cpus;
    int threads;
  };
  std::string first;
  for (const Run& run : {Run{"0", 1}, Run{"0,1", 2}, Run{"0,1", 1}, Run{"0", 2}}) {
    const fs::path out = dir / (std::string(run.cpus) + "-" + std::to_string(run.threads));
    std::string output;
    ASSERT_EQ(test::run_shell("taskset -c " + std::string(run.cpus) + " " + LOOM_RUNNER + " run " + graph +
                                  " --frames 1-6 --target video --no-cache -q --threads " +
                                  std::to_string(run.threads) + " --out " + out.string(),
                              &output),
              0)
        << output;
    const std::string bytes = read_all(out / "twist.mp4");
    ASSERT_GT(bytes.size(), 1000u) << out;
    if (first.empty()) first = bytes;
    EXPECT_TRUE(bytes == first) << "taskset -c " << run.cpus << " --threads " << run.threads
                                << ": the MP4's bytes differ from taskset -c 0 --threads 1's";
  }
}

}  // namespace
}  // namespace loom
