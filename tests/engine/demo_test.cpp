// The quick-start demo (scripts/demo runs graphs/demo.json): it writes every
// file README.md names under out/demo/, and its render shows a lit, textured
// mesh (not a black or flat image).
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "run_loom.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

namespace fs = std::filesystem;

TEST(Demo, WritesEveryFileTheReadmeNamesAndATexturedRender) {
  std::ifstream readme(fs::path(LOOM_SOURCE_DIR) / "README.md");
  std::stringstream text;
  text << readme.rdbuf();
  std::set<std::string> named;
  const std::string s = text.str();
  const std::regex file(R"(out/demo/([A-Za-z0-9_.-]+\.[a-z]+))");
  for (std::sregex_iterator it(s.begin(), s.end(), file), end; it != end; ++it) named.insert((*it)[1]);
  ASSERT_GE(named.size(), 4u) << "README names the demo's files";

  const auto out = test::temp_dir() / "demo";
  std::string log;
  ASSERT_EQ(test::run_loom("run " + (fs::path(LOOM_SOURCE_DIR) / "graphs" / "demo.json").string() + " --out " +
                               out.string(),
                           &log),
            0)
      << log;
  for (const auto& name : named) EXPECT_TRUE(fs::is_regular_file(out / name)) << name << " is named by README";
  EXPECT_EQ(log.find("warning"), std::string::npos) << log;

  // The render: lit (bright pixels), textured (both checker colors on the mesh).
  const cv::Mat render = cv::imread((out / "hemisphere.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(render.empty());
  int white = 0, blue = 0;
  for (int y = 0; y < render.rows; ++y)
    for (int x = 0; x < render.cols; ++x) {
      const cv::Vec3b p = render.at<cv::Vec3b>(y, x);  // BGR
      white += p[0] > 180 && p[1] > 180 && p[2] > 180;
      blue += p[0] > 100 && p[2] < 80;
    }
  const int pixels = render.rows * render.cols;
  EXPECT_GT(white, pixels / 20);
  EXPECT_GT(blue, pixels / 20);
}

}  // namespace
}  // namespace loom
