// The machine's memory bandwidth, STREAM-style (McCalpin 1995): copy
// a = b, scale a = s b, add a = b + c and triad a = b + s c over arrays far
// larger than the last-level cache, on 1 and 2 threads (TBB, a static split so
// each thread touches the same pages it first wrote). Bytes are counted as
// STREAM counts them (8 per double read or written, no write-allocate), and
// the best of the runs is the bandwidth (STREAM's rule), with the median
// beside it. The limit the stencil and particle benchmarks are measured
// against (README's benchmark table).
//
//   bench_stream [--quick] [--mb N] [--threads N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "bench_harness.hpp"

namespace {

struct Kernel {
  const char* name;
  int arrays;  // doubles moved per element
  std::function<void(double*, const double*, const double*, std::size_t, std::size_t)> run;
};

// Runs body(begin, end) over [0, n) split evenly among the threads, the same
// split every time (first touch then places each page with its thread).
void split(std::size_t n, const std::function<void(std::size_t, std::size_t)>& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, n / 64 + 1),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); },
                    tbb::static_partitioner());
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_stream",
                       "Memory bandwidth, STREAM-style: copy, scale, add and triad over arrays much larger "
                       "than the last-level cache, on 1 and 2 threads; best and median GB/s. Writes "
                       "stream.csv and a plot.");
  bool quick = false;
  int megabytes = 256, max_threads = 2;
  cli.quick(quick, "5 runs instead of 20").option("--mb", megabytes, "size of each array in MB (default 256)");
  cli.threads(max_threads, "largest thread count measured (default 2)");
  cli.parse(argc, argv);
  const std::size_t n = std::size_t(std::max(megabytes, 1)) * (1 << 20) / sizeof(double);
  const int runs = quick ? 5 : 20;
  std::vector<double> a(n), b(n), c(n);
  const double s = 3.0;
  const std::vector<Kernel> kernels = {
      {"copy", 2, [](double* x, const double* y, const double*, std::size_t i, std::size_t e) {
         for (; i < e; ++i) x[i] = y[i];
       }},
      {"scale", 2, [s](double* x, const double* y, const double*, std::size_t i, std::size_t e) {
         for (; i < e; ++i) x[i] = s * y[i];
       }},
      {"add", 3, [](double* x, const double* y, const double* z, std::size_t i, std::size_t e) {
         for (; i < e; ++i) x[i] = y[i] + z[i];
       }},
      {"triad", 3, [s](double* x, const double* y, const double* z, std::size_t i, std::size_t e) {
         for (; i < e; ++i) x[i] = y[i] + s * z[i];
       }},
  };
  loom::bench::Csv csv("stream", {"threads", "kernel", "array_mb", "best_gb_per_s", "median_gb_per_s",
                                  "load_average"});
  for (int threads = 1; threads <= std::max(max_threads, 1); ++threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    split(n, [&](std::size_t i, std::size_t e) {  // first touch by the threads that will stream them
      for (; i < e; ++i) a[i] = 1.0, b[i] = 2.0, c[i] = 0.5;
    });
    for (const Kernel& k : kernels) {
      std::vector<double> seconds;
      for (int r = 0; r < runs; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        split(n, [&](std::size_t i, std::size_t e) { k.run(a.data(), b.data(), c.data(), i, e); });
        seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(seconds.begin(), seconds.end());
      const double bytes = double(k.arrays) * sizeof(double) * double(n);
      csv.row({(long long)threads, std::string(k.name), (long long)megabytes, bytes / seconds.front() * 1e-9,
               bytes / seconds[seconds.size() / 2] * 1e-9, loom::bench::load_average()});
    }
  }
  // The result is read, so no compiler can drop the loops.
  double check = 0;
  for (std::size_t i = 0; i < n; i += 4096) check += a[i];
  std::printf("checksum %.1f\n", check);
  csv.save();
  loom::bench::plot(csv, {"threads", "best_gb_per_s", "kernel", "STREAM-style bandwidth (GB/s) by threads",
                          false, false, ""});
  return 0;
}
