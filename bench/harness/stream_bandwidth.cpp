#include "stream_bandwidth.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

namespace loom::bench {
namespace {

constexpr double kScale = 3.0;

// body(begin, end) over [0, n) split evenly among the threads, the same split
// every time (first touch then places each page with its thread).
template <class Body>
void split(std::size_t n, const Body& body) {
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, n / 64 + 1),
      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); }, tbb::static_partitioner());
}

}  // namespace

const std::vector<StreamKernel>& stream_kernels() {
  static const std::vector<StreamKernel> kernels = {
      {"copy", 2,
       [](double* a, const double* b, const double*, std::size_t i, std::size_t e) {
         for (; i < e; ++i) a[i] = b[i];
       }},
      {"scale", 2,
       [](double* a, const double* b, const double*, std::size_t i, std::size_t e) {
         for (; i < e; ++i) a[i] = kScale * b[i];
       }},
      {"add", 3,
       [](double* a, const double* b, const double* c, std::size_t i, std::size_t e) {
         for (; i < e; ++i) a[i] = b[i] + c[i];
       }},
      {"triad", 3,
       [](double* a, const double* b, const double* c, std::size_t i, std::size_t e) {
         for (; i < e; ++i) a[i] = b[i] + kScale * c[i];
       }},
  };
  return kernels;
}

const StreamKernel& stream_kernel(const std::string& name) {
  for (const StreamKernel& k : stream_kernels())
    if (name == k.name) return k;
  throw std::invalid_argument("no STREAM kernel named '" + name + "' (copy, scale, add, triad)");
}

StreamArrays::StreamArrays(std::size_t megabytes) {
  const std::size_t n = std::max<std::size_t>(megabytes, 1) * (1 << 20) / sizeof(double);
  a_.resize(n), b_.resize(n), c_.resize(n);
  touch();
}

void StreamArrays::touch() {
  split(a_.size(), [&](std::size_t i, std::size_t e) {
    for (; i < e; ++i) a_[i] = 1.0, b_[i] = 2.0, c_[i] = 0.5;
  });
}

double StreamArrays::run(const StreamKernel& kernel) {
  const auto t0 = std::chrono::steady_clock::now();
  split(a_.size(), [&](std::size_t i, std::size_t e) { kernel.run(a_.data(), b_.data(), c_.data(), i, e); });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double StreamArrays::bytes(const StreamKernel& kernel) const {
  return double(kernel.arrays) * sizeof(double) * double(a_.size());
}

double StreamArrays::checksum() const {
  double sum = 0;
  for (std::size_t i = 0; i < a_.size(); i += 4096) sum += a_[i];
  return sum;
}

}  // namespace loom::bench
