// Loom and its peers timed in one program, alternating run by run: each round
// runs every contender once in turn, so a change of the machine's load falls
// on all of them alike, and the ratio of their medians survives it.
//
//   auto t = loom::bench::time_alternating(5, {[&] { loom_solve(); }, [&] { peer_solve(); }});
//   double ratio = t[1].wall / t[0].wall;
#pragma once

#include <algorithm>
#include <chrono>
#include <ctime>
#include <functional>
#include <vector>

#include "bench_harness.hpp"

namespace loom::bench {

struct AlternatingTiming {
  double wall = 0, cpu = 0;  // medians, seconds; cpu = this process's CPU time, all threads
};

// `runs` rounds after one warm-up round (none with warm_up = false).
inline std::vector<AlternatingTiming> time_alternating(int runs, const std::vector<std::function<void()>>& contenders,
                                                       bool warm_up = true) {
  if (warm_up)
    for (const auto& f : contenders) f();
  std::vector<std::vector<double>> wall(contenders.size()), cpu(contenders.size());
  for (int r = 0; r < std::max(runs, 1); ++r)
    for (std::size_t k = 0; k < contenders.size(); ++k) {
      const auto w0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      contenders[k]();
      cpu[k].push_back(static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
      wall[k].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count());
    }
  std::vector<AlternatingTiming> out;
  for (std::size_t k = 0; k < contenders.size(); ++k) out.push_back({median(wall[k]), median(cpu[k])});
  return out;
}

}  // namespace loom::bench
