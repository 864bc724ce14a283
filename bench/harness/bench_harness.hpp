// The time-vs-error benchmark harness every bench/ program uses:
// medians of repeated timings, CSV written atomically, PNG plots by gnuplot.
//
//   loom::bench::Csv csv("warp", {"method", "pairs", "seconds", "mpx_per_s"});
//   auto t = loom::bench::time_median([&] { warp(...); }, 5);
//   csv.row({"rbf", 64, t.median, 1.0 / t.median});
//   csv.save();   // bench/results/warp.csv (or $LOOM_BENCH_OUT/warp.csv)
//   loom::bench::plot(csv, {"pairs", "mpx_per_s", "method", "Warp throughput"});
#pragma once

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

namespace loom::bench {

// CPU seconds (user + system) of this whole process, every thread included.
double process_cpu_seconds();
// The 1-minute load average, to report beside every figure (0 if unknown).
double load_average();

struct Timing {
  double median = 0, min = 0, max = 0;  // seconds
  int runs = 0;
};

// Runs f once to warm up, then `runs` times; returns the median and extremes.
template <class F>
Timing time_median(F&& f, int runs = 5) {
  f();
  std::vector<double> t;
  for (int i = 0; i < runs; ++i) {
    auto start = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::vector<double> sorted = t;
  std::sort(sorted.begin(), sorted.end());
  Timing r;
  r.runs = runs;
  r.min = sorted.front();
  r.max = sorted.back();
  r.median = runs % 2 ? sorted[runs / 2] : (sorted[runs / 2 - 1] + sorted[runs / 2]) / 2;
  return r;
}

using Cell = std::variant<std::string, double, long long>;

class Csv {
 public:
  Csv(std::string name, std::vector<std::string> columns);
  void row(std::vector<Cell> cells);  // also echoed to stdout as an aligned table
  // Writes <results>/<name>.csv atomically; returns its path.
  std::filesystem::path save() const;
  const std::string& name() const { return name_; }
  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<std::vector<Cell>>& rows() const { return rows_; }

 private:
  std::string name_;
  std::vector<std::string> columns_;
  std::vector<std::vector<Cell>> rows_;
};

struct PlotSpec {
  std::string x, y;       // column names
  std::string group;      // one line per distinct value of this column ("" for one)
  std::string title;
  bool log_x = false, log_y = false;
  std::string file_suffix;  // <name><suffix>.png, for several plots of one CSV
};

// Draws <results>/<name><suffix>.png with gnuplot; prints a note and returns
// false (never fails the benchmark) when gnuplot is missing.
bool plot(const Csv& csv, const PlotSpec& spec);

// Prints `usage` and exits 0 when the arguments contain --help or -h.
void handle_help(int argc, char** argv, const char* usage);

// bench/results in the source tree, or $LOOM_BENCH_OUT.
std::filesystem::path results_dir();

// ../shared/data/<relative>, or an empty path when absent.
std::filesystem::path data_file(const std::string& relative);

}  // namespace loom::bench
