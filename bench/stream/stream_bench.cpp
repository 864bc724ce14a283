// The machine's memory bandwidth, STREAM-style (McCalpin 1995): copy
// a = b, scale a = s b, add a = b + c and triad a = b + s c over arrays far
// larger than the last-level cache, on 1 and 2 threads (the kernels and the
// thread split: bench/harness/stream_bandwidth). The best of the runs is the
// bandwidth (STREAM's rule), with the median beside it. The limit the
// stencil and particle benchmarks are measured against (README's benchmark
// table).
//
//   bench_stream [--quick] [--mb N] [--threads N]
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "bench_harness.hpp"
#include "stream_bandwidth.hpp"

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
  const int runs = quick ? 5 : 20;
  loom::bench::StreamArrays arrays(static_cast<std::size_t>(std::max(megabytes, 1)));
  loom::bench::Csv csv("stream", {"threads", "kernel", "array_mb", "best_gb_per_s", "median_gb_per_s",
                                  "load_average"});
  for (int threads = 1; threads <= std::max(max_threads, 1); ++threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    arrays.touch();  // first touch by the threads that will stream them
    for (const loom::bench::StreamKernel& k : loom::bench::stream_kernels()) {
      std::vector<double> seconds;
      for (int r = 0; r < runs; ++r) seconds.push_back(arrays.run(k));
      std::sort(seconds.begin(), seconds.end());
      csv.row({(long long)threads, std::string(k.name), (long long)megabytes, arrays.bytes(k) / seconds.front() * 1e-9,
               arrays.bytes(k) / seconds[seconds.size() / 2] * 1e-9, loom::bench::load_average()});
    }
  }
  std::printf("checksum %.1f\n", arrays.checksum());
  csv.save();
  loom::bench::plot(csv, {"threads", "best_gb_per_s", "kernel", "STREAM-style bandwidth (GB/s) by threads",
                          false, false, ""});
  return 0;
}
