// bench_cold's OpenCV peer: cv::seamlessClone on image files as a user calls
// it, each call timed in one process. The first call is the cold figure (a
// fresh process: OpenCV's own set-up and first touches of its buffers), the
// later ones the warm figure, as a benchmark's loop measures it.
//
//   poisson_opencv_peer SOURCE TARGET MASK CENTRE_X CENTRE_Y CALLS
//
// prints one line per call: its wall seconds.
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/photo.hpp>

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: %s SOURCE TARGET MASK CENTRE_X CENTRE_Y CALLS\n", argv[0]);
    return 2;
  }
  const cv::Mat source = cv::imread(argv[1], cv::IMREAD_COLOR), target = cv::imread(argv[2], cv::IMREAD_COLOR);
  const cv::Mat mask = cv::imread(argv[3], cv::IMREAD_GRAYSCALE);
  if (source.empty() || target.empty() || mask.empty()) {
    std::fprintf(stderr, "error: cannot read %s, %s or %s\n", argv[1], argv[2], argv[3]);
    return 1;
  }
  const cv::Point centre(std::atoi(argv[4]), std::atoi(argv[5]));
  const int calls = std::atoi(argv[6]);
  cv::Mat blended;
  for (int k = 0; k < calls; ++k) {
    const auto start = std::chrono::steady_clock::now();
    cv::seamlessClone(source, target, mask, centre, blended, cv::NORMAL_CLONE);
    std::printf("%.6f\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return 0;
}
