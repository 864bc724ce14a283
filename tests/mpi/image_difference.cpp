// image_difference A B: the largest difference between two float images
// (EXR, read by OpenCV), absolute and relative to the larger value, and
// whether their sizes and channels agree, A's smallest and largest value, and
// the sum of A's first channel (a samples AOV: every sample taken).
// For the MPI tests' "equal within float rounding"; prints JSON:
// {"same_shape": ..., "max_abs": ..., "max_rel": ..., "min_a": ..., "max_a": ..., "sum_a": ...}.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgcodecs.hpp>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: image_difference A.exr B.exr\n");
    return 2;
  }
  const cv::Mat a = cv::imread(argv[1], cv::IMREAD_UNCHANGED), b = cv::imread(argv[2], cv::IMREAD_UNCHANGED);
  if (a.empty() || b.empty()) {
    std::fprintf(stderr, "image_difference: cannot read %s\n", a.empty() ? argv[1] : argv[2]);
    return 2;
  }
  if (a.size() != b.size() || a.type() != b.type() || a.depth() != CV_32F) {
    std::printf("{\"same_shape\": false}\n");
    return 0;
  }
  double max_abs = 0, max_rel = 0, min_a = 1e300, max_a = -1e300, sum_a = 0;
  for (int y = 0; y < a.rows; ++y) {
    const float* p = a.ptr<float>(y);
    const float* q = b.ptr<float>(y);
    for (int x = 0; x < a.cols; ++x) sum_a += p[x * a.channels()];
    for (int i = 0; i < a.cols * a.channels(); ++i) {
      const double d = std::abs(double(p[i]) - q[i]);
      min_a = std::min(min_a, double(p[i]));
      max_a = std::max(max_a, double(p[i]));
      max_abs = std::max(max_abs, d);
      max_rel = std::max(max_rel, d / std::max({std::abs(double(p[i])), std::abs(double(q[i])), 1e-30}));
    }
  }
  std::printf("{\"same_shape\": true, \"max_abs\": %.9g, \"max_rel\": %.9g, \"min_a\": %.9g, \"max_a\": %.9g, "
              "\"sum_a\": %.17g}\n",
              max_abs, max_rel, min_a, max_a, sum_a);
  return 0;
}
