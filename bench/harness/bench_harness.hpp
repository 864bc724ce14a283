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
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace loom::bench {

// CPU seconds (user + system) of this whole process, every thread included.
double process_cpu_seconds();
// The 1-minute load average, to report beside every figure (0 if unknown).
double load_average();

// The median of v: its middle value, the mean of the middle two for an even
// count; 0 for none.
inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 ? v[h] : (v[h - 1] + v[h]) / 2;
}

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
  Timing r;
  r.runs = runs;
  r.min = *std::min_element(t.begin(), t.end());
  r.max = *std::max_element(t.begin(), t.end());
  r.median = median(t);
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

// A part of a benchmark that its command line can ask for by name.
struct Mode {
  std::string name, help;
};

// The command line of a benchmark, parsed by CLI11, so that every benchmark
// spells the same things alike, lists them with --help and refuses what it
// does not know (a message and exit 2):
//   --out DIR      where CSV and plots go (every benchmark; else $LOOM_BENCH_OUT,
//                  else bench/results)
//   --quick        fewer sizes and runs
//   --threads N    at most N TBB worker threads (0: all cores), in the
//                  benchmarks whose work runs on TBB
//   MODE ...       positional names of the parts to run (none: the default set)
//
//   loom::bench::Cli cli("bench_warp", "ImageWarp against OpenCV's thin-plate spline ...");
//   bool quick = false;
//   cli.quick(quick, "64 pairs, 3 runs").threads();
//   cli.parse(argc, argv);
class Cli {
 public:
  Cli(const std::string& program, const std::string& description);
  ~Cli();
  Cli(const Cli&) = delete;
  Cli& operator=(const Cli&) = delete;

  Cli& quick(bool& value, const std::string& what);
  // --threads N: caps TBB's workers for the whole run when given. With
  // `value`, the benchmark also reads N (its default stays when not given).
  Cli& threads(const std::string& help = "at most N TBB worker threads (0: all cores)");
  Cli& threads(int& value, const std::string& help);
  Cli& flag(const std::string& name, bool& value, const std::string& help);
  Cli& option(const std::string& name, int& value, const std::string& help);
  Cli& option(const std::string& name, double& value, const std::string& help);
  Cli& option(const std::string& name, std::string& value, const std::string& help);
  // Where results go without --out, for a program that writes elsewhere than
  // bench/results (`what` names them in --help: "The figures").
  Cli& results(const std::filesystem::path& dir, const std::string& what);
  // Positional mode names, each checked against `modes` and listed by --help.
  Cli& modes(std::vector<std::string>& chosen, const std::vector<Mode>& modes, const std::string& help);

  // Parses the arguments: prints the help and exits 0 on --help; prints what
  // is wrong and exits 2 on an unknown option or a bad value.
  void parse(int argc, char** argv);
  // Whether the option `name` ("--out", "--density") was on the command line.
  bool given(const std::string& name) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Whether `chosen` (from Cli::modes) asks for `mode`; no mode chosen asks for all.
bool wants(const std::vector<std::string>& chosen, const std::string& mode);

// --out, else the folder given to Cli::results, else $LOOM_BENCH_OUT, else
// bench/results in the source tree.
std::filesystem::path results_dir();

// The Loom source tree.
std::filesystem::path source_dir();

// ../shared/data/<relative>, or an empty path when absent.
std::filesystem::path data_file(const std::string& relative);

}  // namespace loom::bench
