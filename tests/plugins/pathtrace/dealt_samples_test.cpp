// PathTrace split by samples and dealt as parts ask (PixelRegion::dealt,
// Context::take_slot), two parts simulated in one process: each takes some
// of every pass's slots, in any order; together they must take every sample
// of every pixel exactly once, and their sums must make one process's image.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "loom/evaluator.hpp"
#include "loom/image.hpp"
#include "loom/testing.hpp"

namespace loom {
namespace {

constexpr int kSlots = 256;

// One part: takes the slots `mine` of each pass, in that order; its sums are
// not added to the other part's (sum does nothing), so its images are its
// own samples' means.
class SlotsSplit final : public PixelSplit {
 public:
  explicit SlotsSplit(std::vector<int> mine) : mine_(std::move(mine)) {}
  PixelRegion region(const std::string& node) const override {
    return node == "pt" ? PixelRegion{32, 0, 2, true, kSlots} : PixelRegion{};
  }
  void combine(const std::string&, const NodeSpec&, std::vector<Value>&) const override {}
  void sum(double*, std::size_t, double) const override { next_ = 0; }
  int take_slot() const override { return next_ < mine_.size() ? mine_[next_++] : -1; }

 private:
  std::vector<int> mine_;
  mutable std::size_t next_ = 0;
};

struct Images {
  cv::Mat image, samples;
};

Images render(int spp, const PixelSplit* split) {
  testing::Engine e;
  const json doc = {{"loom", 1},
                    {"seed", 5},
                    {"nodes",
                     {{"box", {{"type", "CornellBox"}}},
                      {"pt",
                       {{"type", "PathTrace"},
                        {"inputs", {{"scene", {{"from", "box.scene"}}}, {"size", {24, 16}}, {"spp", spp}}}}}}}};
  EvalOptions o;
  o.targets = {parse_target("pt.image"), parse_target("pt.samples")};
  o.pixel_split = split;
  const EvalResult r = e.session().evaluate(e.load(doc), o);
  EXPECT_TRUE(r.ok()) << r.nodes.at("pt").error;
  return {r.outputs.at("pt.image").at(0).as<Image>().pixels, r.outputs.at("pt.samples").at(0).as<Image>().pixels};
}

TEST(PathTraceDealtSamples, TwoPartsTakeEverySampleOnceAndSumToOneProcessImage) {
  std::vector<int> first, second;  // one part every third slot, backwards; the other the rest
  for (int s = kSlots - 1; s >= 0; --s) (s % 3 == 0 ? first : second).push_back(s);
  std::reverse(second.begin() + 10, second.end());
  for (int spp : {1, 20, 300}) {  // 300: a pixel takes two samples of some slots
    const Images whole = render(spp, nullptr);
    const SlotsSplit split_a(first), split_b(second);
    const Images a = render(spp, &split_a), b = render(spp, &split_b);
    int fewer_in_a = 0;
    for (int y = 0; y < whole.image.rows; ++y)
      for (int x = 0; x < whole.image.cols; ++x) {
        const float na = a.samples.at<float>(y, x), nb = b.samples.at<float>(y, x);
        ASSERT_EQ(na + nb, float(spp)) << spp << " spp, pixel " << x << "," << y;
        fewer_in_a += na < nb;
        for (int c = 0; c < 3; ++c) {
          const double sum = double(a.image.at<cv::Vec3f>(y, x)[c]) * na + double(b.image.at<cv::Vec3f>(y, x)[c]) * nb;
          EXPECT_NEAR(sum / spp, whole.image.at<cv::Vec3f>(y, x)[c], 1e-5 * (1 + whole.image.at<cv::Vec3f>(y, x)[c]))
              << spp << " spp, pixel " << x << "," << y;
        }
      }
    if (spp >= 20) {
      EXPECT_GT(fewer_in_a, int(whole.image.total() / 2)) << "a third of the slots: about a third of the samples";
    }
  }
}

}  // namespace
}  // namespace loom
