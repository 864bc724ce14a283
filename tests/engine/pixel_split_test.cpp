// The engine's side of an image split over processes (EvalOptions::pixel_split),
// in one process: a split that deals parts one after another, as an MPI run
// with --mpi-deal dynamic does, gets the node's body run once per part.
#include <gtest/gtest.h>

#include "loom/image.hpp"
#include "loom/testing.hpp"
#include "test_files.hpp"

namespace loom {
namespace {

// Hands over parts 0..parts-1 in turn, keeping each part's tiles; after the
// last, the outputs become the kept image.
class DealingSplit final : public PixelSplit {
 public:
  DealingSplit(std::string node, int tile, int parts) : node_(std::move(node)), tile_(tile), parts_(parts) {}

  PixelRegion region(const std::string& node) const override {
    return node == node_ ? PixelRegion{tile_, part_, parts_, false, 0} : PixelRegion{};
  }
  void combine(const std::string&, const NodeSpec&, std::vector<Value>& outputs) const override {
    ++combines;
    const cv::Mat& part = outputs[0].as<Image>().pixels;
    if (kept_.empty()) kept_ = part.clone();
    const int columns = (part.cols + tile_ - 1) / tile_, rows = (part.rows + tile_ - 1) / tile_;
    for (int t = part_; t < columns * rows; t += parts_) {
      const int x = (t % columns) * tile_, y = (t / columns) * tile_;
      const cv::Rect r(x, y, std::min(tile_, part.cols - x), std::min(tile_, part.rows - y));
      part(r).copyTo(kept_(r));
    }
    if (++part_ < parts_) return;  // the engine runs the body on the next part
    --part_;                        // region() unchanged: gathered
    outputs[0] = Value::make<Image>(Image(kept_, outputs[0].as<Image>().encoding));
  }
  void sum(double*, std::size_t, double) const override {}

  mutable int combines = 0;

 private:
  std::string node_;
  int tile_, parts_;
  mutable int part_ = 0;
  mutable cv::Mat kept_;
};

const cv::Mat& posterized(testing::Engine& e, const Graph& g, const PixelSplit* split, EvalResult& r) {
  EvalOptions o;
  o.targets = {parse_target("poster.image")};
  o.output_dir = test::temp_dir();
  o.pixel_split = split;
  r = e.session().evaluate(g, o);
  return r.outputs.at("poster.image").at(0).as<Image>().pixels;
}

TEST(PixelSplit, APartHandedOverInCombineRunsTheBodyAgainUntilEveryPartIsDone) {
  testing::Engine e;
  const Graph g = e.load(json{
      {"loom", 1},
      {"nodes",
       {{"board", {{"type", "Checkerboard"}, {"inputs", {{"size", {45, 31}}, {"cells", 5}}}}},
        {"poster", {{"type", "Posterize"}, {"inputs", {{"image", {{"from", "board.image"}}}, {"levels", 3}}}}}}}});
  EvalResult whole_run, split_run;
  const cv::Mat whole = posterized(e, g, nullptr, whole_run).clone();
  e.session().clear_cache();
  const DealingSplit split("poster", 4, 7);  // 12 x 8 tiles, 7 parts
  const cv::Mat dealt = posterized(e, g, &split, split_run);
  ASSERT_TRUE(split_run.ok());
  EXPECT_EQ(split.combines, 7);
  ASSERT_EQ(dealt.size, whole.size);
  EXPECT_EQ(cv::norm(dealt, whole, cv::NORM_INF), 0.0);  // every part's tiles, bit for bit
  EXPECT_EQ(split_run.nodes.at("poster").runs, 1);        // one run of the node, its body 7 times
}

}  // namespace
}  // namespace loom
