// The machine's memory bandwidth, STREAM-style (McCalpin 1995): copy a = b,
// scale a = s b, add a = b + c and triad a = b + s c over arrays far larger
// than the last-level cache. Bytes are counted as STREAM counts them (8 per
// double read or written, no write-allocate). bench_stream reports all four;
// the stencil and particle benchmarks time the triad beside their own runs
// (the limit of README's benchmark table).
//
//   loom::bench::StreamArrays arrays(256);            // 3 × 256 MB
//   const auto& triad = loom::bench::stream_kernel("triad");
//   double seconds = arrays.run(triad);
//   double gb_per_s = arrays.bytes(triad) / seconds * 1e-9;
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace loom::bench {

struct StreamKernel {
  const char* name;
  int arrays;  // doubles moved per element
  void (*run)(double* a, const double* b, const double* c, std::size_t begin, std::size_t end);
};

// copy, scale, add, triad (STREAM's order).
const std::vector<StreamKernel>& stream_kernels();
// The kernel of that name; throws std::invalid_argument for another name.
const StreamKernel& stream_kernel(const std::string& name);

// Three arrays of `megabytes` each. Every run splits [0, n) evenly among the
// threads of the current TBB limit, the same split every time, so that pages
// stay with the thread that first touched them (call touch() again after
// changing the limit).
class StreamArrays {
 public:
  explicit StreamArrays(std::size_t megabytes);
  void touch();
  // Seconds of one run of `kernel` over the arrays.
  double run(const StreamKernel& kernel);
  // Bytes one run moves, as STREAM counts them.
  double bytes(const StreamKernel& kernel) const;
  // A sum of the results, to print, so that no compiler drops the loops.
  double checksum() const;

 private:
  std::vector<double> a_, b_, c_;
};

}  // namespace loom::bench
