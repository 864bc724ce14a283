// Large images on transparent huge pages (engine/types/image_memory.cpp).
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "loom/image.hpp"

namespace {

// The "THPeligible" flag of the mapping holding `address` in /proc/self/smaps
// (-1: no such field, an old kernel).
int thp_eligible(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto a = reinterpret_cast<std::uintptr_t>(address);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> lo >> dash >> hi && dash == '-' && line.find(':') > line.find(' ')) {
      inside = a >= lo && a < hi;
      continue;
    }
    if (inside && line.rfind("THPeligible:", 0) == 0) return std::stoi(line.substr(12));
  }
  return -1;
}

TEST(ImageMemory, ALargeImageIsOnHugePagesAndASmallOneIsNot) {
  // A 3840x2160 RGB float image, as given from NumPy or traced.
  const loom::Image large(cv::Mat(2160, 3840, CV_32FC3, cv::Scalar(0.25f, 0.5f, 1.0f)), loom::Encoding::linear);
  const auto* data = large.pixels.data;
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(data) % (std::uintptr_t(1) << 21), 0u) << "2-MB aligned";
  EXPECT_NE(large.pixels.u->currAllocator, cv::Mat::getStdAllocator());
  const std::string enabled = [] {
    std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string s;
    std::getline(f, s);
    return s;
  }();
  if (enabled.find("[never]") == std::string::npos) {
    const int eligible = thp_eligible(data);
    if (eligible >= 0) {
      EXPECT_EQ(eligible, 1) << "the kernel was not asked for huge pages (THP: " << enabled << ")";
    }
  }
  // Its pixels are ordinary memory: written, copied, compared, freed.
  cv::Mat copy = large.pixels.clone();
  EXPECT_EQ(cv::norm(copy, large.pixels, cv::NORM_INF), 0.0);
  EXPECT_FLOAT_EQ(copy.at<cv::Vec3f>(2159, 3839)[2], 1.0f);

  const cv::Mat small(64, 64, CV_32FC3);
  EXPECT_EQ(small.u->currAllocator, cv::Mat::getStdAllocator()) << "small buffers keep OpenCV's allocator";
}

TEST(ImageMemory, AViewOverUserMemoryIsNotTakenOver) {
  std::vector<float> user(2160 * 3840 * 3, 0.5f);
  const cv::Mat view(2160, 3840, CV_32FC3, user.data());
  EXPECT_EQ(view.data, reinterpret_cast<uchar*>(user.data()));
  cv::Mat region = view(cv::Rect(10, 10, 100, 100)).clone();
  EXPECT_EQ(region.at<cv::Vec3f>(5, 5)[0], 0.5f);
}

}  // namespace
