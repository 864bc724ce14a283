// `loom run --preview`: a long PathTrace shows its passes in a preview file
// while it runs, and Ctrl-C (SIGINT) ends it within half a second (issue 37),
// with no final file written.
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "runner_helpers.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

// The Cornell box path traced at width x height and `spp` into final.png.
fs::path cornell_trace_graph(const fs::path& dir, int width, int height, int spp) {
  return test::write_graph(
      dir,
      {{"loom", 1},
       {"nodes",
        {{"box", {{"type", "CornellBox"}}},
         {"pt",
          {{"type", "PathTrace"},
           {"inputs", {{"scene", test::from("box.scene")}, {"size", {width, height}}, {"spp", spp}}}}},
         {"save", {{"type", "SaveImage"}, {"inputs", {{"image", test::from("pt.image")}, {"path", "final.png"}}}}}}}});
}

TEST(RunnerPreview, APathTraceIsPreviewedWhileItRunsAndSigintEndsItWithinHalfASecond) {
  const auto dir = test::temp_dir();
  const auto g = cornell_trace_graph(dir, 640, 480, 4096);
  const fs::path preview = dir / "preview.png", out = dir / "out";
  // Started in the background; once the preview file exists (the first
  // passes are done and the render is well under way), SIGINT, timed.
  const std::string script =
      "env LOOM_PLUGIN_PATH=" LOOM_TEST_PLUGIN_DIR " " LOOM_RUNNER " run " + g.string() + " --no-cache --out " +
      out.string() + " --preview " + preview.string() + " --preview-every 0.1 > " + (dir / "log").string() +
      " 2>&1 & pid=$!; for i in $(seq 600); do [ -s " + preview.string() +
      " ] && break; sleep 0.05; done; sleep 0.3; t0=$(date +%s.%N); kill -INT $pid; wait $pid; code=$?; "
      "t1=$(date +%s.%N); echo \"exit $code after $(awk \"BEGIN{print $t1 - $t0}\") s\"";
  std::string printed;
  test::run_shell(script, &printed);
  std::printf("%s", printed.c_str());
  ASSERT_NE(printed.find("exit "), std::string::npos) << printed;
  std::istringstream in(printed.substr(printed.find("exit ")));
  std::string word;
  int code = -1;
  double seconds = 1e9;
  in >> word >> code >> word >> seconds;
  EXPECT_EQ(code, 130) << printed << test::read_text(dir / "log");
  EXPECT_LT(seconds, 0.5) << printed;
  // The preview is a whole image of the render so far: PNG, 640x480, lit.
  const cv::Mat shown = cv::imread(preview.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(shown.empty()) << test::read_text(dir / "log");
  EXPECT_EQ(shown.cols, 640);
  EXPECT_EQ(shown.rows, 480);
  EXPECT_GT(cv::mean(shown)[2], 20);  // the red wall and the warm light
  EXPECT_FALSE(fs::exists(out / "final.png"));  // the sink never saw a partial image
}

// SaveImage writes the preview through call_node (loom/call_node.hpp), its
// inputs other than the image and the path at their defaults: each must live
// while SaveImage's body reads it (it once read "tiled" from a value already
// freed, which ThreadSanitizer and AddressSanitizer report; a sanitized
// runner then exits 66 or aborts instead of 0).
TEST(RunnerPreview, APreviewedRunThatEndsWritesThePreviewAndTheResult) {
  const auto dir = test::temp_dir();
  const auto g = cornell_trace_graph(dir, 64, 48, 8);
  const fs::path preview = dir / "preview.png", out = dir / "out";
  std::string printed;
  EXPECT_EQ(test::run_loom("run " + g.string() + " --no-cache -q --out " + out.string() + " --preview " +
                               preview.string() + " --preview-every 0",
                           &printed),
            0)
      << printed;
  const cv::Mat shown = cv::imread(preview.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(shown.empty()) << printed;
  EXPECT_EQ(shown.cols, 64);
  EXPECT_EQ(shown.rows, 48);
  EXPECT_TRUE(fs::exists(out / "final.png")) << printed;
}

}  // namespace
}  // namespace loom
