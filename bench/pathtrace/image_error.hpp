// Error of an image against a reference, the PFM files the peers write, and
// the PNGs this benchmark writes.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include <opencv2/core.hpp>

#include "bench_harness.hpp"
#include "image_codec.hpp"
#include "loom/image.hpp"

namespace loom::pathtrace::bench {

// relMSE = mean over pixels and channels of (x - ref)² / (ref² + 0.01).
inline double rel_mse(const cv::Mat& x, const cv::Mat& ref) {
  cv::Mat a, b;
  x.convertTo(a, CV_64F);
  ref.convertTo(b, CV_64F);
  cv::Mat d = a - b;
  cv::Mat r = d.mul(d) / (b.mul(b) + cv::Scalar::all(0.01));
  return cv::mean(r.reshape(1))[0];
}

// A 3-channel little-endian PFM (rows bottom to top); empty if unreadable.
inline cv::Mat read_pfm(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::string magic;
  int w = 0, h = 0;
  double scale = 0;
  f >> magic >> w >> h >> scale;
  f.get();
  if (magic != "PF" || w <= 0 || h <= 0 || scale >= 0) return {};
  cv::Mat m(h, w, CV_32FC3);
  for (int y = h - 1; y >= 0; --y) f.read(reinterpret_cast<char*>(m.ptr<float>(y)), std::streamsize(w) * 12);
  return f ? m : cv::Mat();
}

// A linear image as an 8-bit PNG <results>/pathtrace/<name>.
inline void save_png(const cv::Mat& image, const std::string& name) {
  const std::filesystem::path dir = loom::bench::results_dir() / "pathtrace";
  std::filesystem::create_directories(dir);
  loom::io::write_image(loom::Image(image, loom::Encoding::linear), dir / name, loom::io::Depth::u8);
}

}  // namespace loom::pathtrace::bench
