#include "bench_harness.hpp"

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "loom/atomic_file.hpp"

namespace loom::bench {

namespace fs = std::filesystem;

double process_cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double load_average() {
  std::ifstream f("/proc/loadavg");
  double load = 0;
  f >> load;
  return load;
}

namespace {
std::string text(const Cell& c) {
  if (const auto* s = std::get_if<std::string>(&c)) return *s;
  if (const auto* i = std::get_if<long long>(&c)) return std::to_string(*i);
  std::ostringstream o;
  o << std::setprecision(6) << std::get<double>(c);
  return o.str();
}
std::string quoted(const std::string& s) {
  return s.find_first_of(",\"") == std::string::npos ? s : "\"" + s + "\"";
}
}  // namespace

Csv::Csv(std::string name, std::vector<std::string> columns)
    : name_(std::move(name)), columns_(std::move(columns)) {
  for (const auto& c : columns_) std::cout << std::setw(14) << c << " ";
  std::cout << std::endl;
}

void Csv::row(std::vector<Cell> cells) {
  if (cells.size() != columns_.size()) {
    std::cerr << "bench " << name_ << ": a row has " << cells.size() << " cells for "
              << columns_.size() << " columns\n";
    std::exit(2);
  }
  for (const auto& c : cells) std::cout << std::setw(14) << text(c) << " ";
  std::cout << std::endl;
  rows_.push_back(std::move(cells));
}

fs::path Csv::save() const {
  std::ostringstream o;
  for (std::size_t i = 0; i < columns_.size(); ++i) o << (i ? "," : "") << quoted(columns_[i]);
  o << "\n";
  for (const auto& r : rows_) {
    for (std::size_t i = 0; i < r.size(); ++i) o << (i ? "," : "") << quoted(text(r[i]));
    o << "\n";
  }
  fs::path path = results_dir() / (name_ + ".csv");
  write_file_atomic(path, o.str());
  std::cout << "wrote " << path.string() << std::endl;
  return path;
}

bool plot(const Csv& csv, const PlotSpec& spec) {
  auto column = [&](const std::string& name) -> int {
    for (std::size_t i = 0; i < csv.columns().size(); ++i)
      if (csv.columns()[i] == name) return static_cast<int>(i);
    return -1;
  };
  const int xi = column(spec.x), yi = column(spec.y), gi = spec.group.empty() ? -1 : column(spec.group);
  if (xi < 0 || yi < 0 || (!spec.group.empty() && gi < 0)) {
    std::cerr << "plot " << csv.name() << ": unknown column\n";
    return false;
  }
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::cerr << "note: gnuplot not found, no plot for " << csv.name() << " (apt-get install gnuplot-nox)\n";
    return false;
  }
  std::map<std::string, std::vector<std::pair<std::string, std::string>>> series;
  for (const auto& r : csv.rows())
    series[gi < 0 ? spec.y : text(r[static_cast<std::size_t>(gi)])].emplace_back(
        text(r[static_cast<std::size_t>(xi)]), text(r[static_cast<std::size_t>(yi)]));

  fs::path png = results_dir() / (csv.name() + spec.file_suffix + ".png");
  fs::path tmp = fs::temp_directory_path() / ("loom-plot-" + csv.name() + spec.file_suffix);
  fs::create_directories(tmp);
  std::ostringstream gp;
  gp << "set terminal pngcairo size 900,600 font 'sans,11'\n"
     << "set output '" << png.string() << ".tmp'\n"
     << "set title '" << (spec.title.empty() ? csv.name() : spec.title) << "'\n"
     << "set xlabel '" << spec.x << "'\nset ylabel '" << spec.y << "'\n"
     << "set termoption noenhanced\nset key outside right\nset grid\n";
  if (spec.log_x) gp << "set logscale x\n";
  if (spec.log_y) gp << "set logscale y\n";
  gp << "plot ";
  int k = 0;
  for (const auto& [name, points] : series) {
    fs::path dat = tmp / ("s" + std::to_string(k) + ".dat");
    std::ofstream d(dat);
    for (const auto& [x, y] : points) d << x << " " << y << "\n";
    gp << (k ? ", " : "") << "'" << dat.string() << "' using 1:2 with linespoints title '" << name << "'";
    ++k;
  }
  gp << "\n";
  fs::path script = tmp / "plot.gp";
  std::ofstream(script) << gp.str();
  bool ok = std::system(("gnuplot '" + script.string() + "'").c_str()) == 0;
  std::error_code ec;
  if (ok) fs::rename(png.string() + ".tmp", png, ec);
  fs::remove_all(tmp, ec);
  if (ok) std::cout << "wrote " << png.string() << std::endl;
  return ok && !ec;
}

void handle_help(int argc, char** argv, const char* usage) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::cout << usage << "\nResults (CSV, PNG) go to " << results_dir().string()
                << " (set LOOM_BENCH_OUT to change).\n";
      std::exit(0);
    }
}

fs::path results_dir() {
  if (const char* env = std::getenv("LOOM_BENCH_OUT")) return env;
  return fs::path(LOOM_SOURCE_DIR) / "bench" / "results";
}

fs::path data_file(const std::string& relative) {
  fs::path p = fs::path(LOOM_SOURCE_DIR) / ".." / "shared" / "data" / relative;
  return fs::exists(p) ? p.lexically_normal() : fs::path();
}

}  // namespace loom::bench
