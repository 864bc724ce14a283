#include "bench_harness.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

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

namespace {
std::string g_out;          // --out, when given
fs::path g_results;         // Cli::results
std::string g_what = "Results (CSV, PNG)";
}  // namespace

struct Cli::Impl {
  CLI::App app;
  std::vector<Mode> modes;
  CLI::Option* threads = nullptr;
  int threads_value = 0;
  int* threads_target = nullptr;
  std::unique_ptr<tbb::global_control> limit;
  Impl(const std::string& program, const std::string& description) : app(description, program) {}
};

Cli::Cli(const std::string& program, const std::string& description)
    : impl_(std::make_unique<Impl>(program, description)) {
  impl_->app.add_option("--out", g_out, "folder for the results (default: below)")
      ->type_name("DIR");
}

Cli::~Cli() = default;

Cli& Cli::quick(bool& value, const std::string& what) { return flag("--quick", value, what); }

Cli& Cli::threads(const std::string& help) {
  impl_->threads =
      impl_->app.add_option("--threads", impl_->threads_value, help)->check(CLI::Range(0, 1 << 16))->type_name("N");
  return *this;
}

Cli& Cli::threads(int& value, const std::string& help) {
  impl_->threads_target = &value;
  impl_->threads_value = value;
  impl_->threads = impl_->app.add_option("--threads", impl_->threads_value, help)
                       ->check(CLI::Range(0, 1 << 16))
                       ->type_name("N")
                       ->capture_default_str();
  return *this;
}

Cli& Cli::flag(const std::string& name, bool& value, const std::string& help) {
  impl_->app.add_flag(name, value, help);
  return *this;
}

Cli& Cli::option(const std::string& name, int& value, const std::string& help) {
  impl_->app.add_option(name, value, help)->capture_default_str();
  return *this;
}

Cli& Cli::option(const std::string& name, double& value, const std::string& help) {
  impl_->app.add_option(name, value, help)->capture_default_str();
  return *this;
}

Cli& Cli::option(const std::string& name, std::string& value, const std::string& help) {
  impl_->app.add_option(name, value, help);
  return *this;
}

Cli& Cli::results(const fs::path& dir, const std::string& what) {
  g_results = dir;
  g_what = what;
  return *this;
}

Cli& Cli::modes(std::vector<std::string>& chosen, const std::vector<Mode>& modes, const std::string& help) {
  impl_->modes = modes;
  std::vector<std::string> names;
  for (const Mode& m : modes) names.push_back(m.name);
  impl_->app.add_option("mode", chosen, help)->check(CLI::IsMember(names));
  return *this;
}

void Cli::parse(int argc, char** argv) {
  std::ostringstream footer;
  if (!impl_->modes.empty()) {
    footer << "Modes:\n";
    std::size_t width = 0;
    for (const Mode& m : impl_->modes) width = std::max(width, m.name.size());
    for (const Mode& m : impl_->modes)
      footer << "  " << std::left << std::setw(static_cast<int>(width) + 2) << m.name << m.help << "\n";
    footer << "\n";
  }
  footer << g_what << " go to " << results_dir().string() << " (--out to change).";
  impl_->app.footer(footer.str());
  try {
    impl_->app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) std::exit(impl_->app.exit(e));  // --help
    const std::string program = impl_->app.get_name();
    std::cerr << program << ": " << e.what() << "\nRun " << program << " --help for its options and modes.\n";
    std::exit(2);
  }
  if (impl_->threads && impl_->threads->count() > 0) {
    if (impl_->threads_target) *impl_->threads_target = impl_->threads_value;
    if (impl_->threads_value > 0)
      impl_->limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                           static_cast<std::size_t>(impl_->threads_value));
  }
}

bool Cli::given(const std::string& name) const { return impl_->app.count(name) > 0; }

bool wants(const std::vector<std::string>& chosen, const std::string& mode) {
  return chosen.empty() || std::find(chosen.begin(), chosen.end(), mode) != chosen.end();
}

fs::path results_dir() {
  if (!g_out.empty()) return g_out;
  if (!g_results.empty()) return g_results;
  if (const char* env = std::getenv("LOOM_BENCH_OUT")) return env;
  return source_dir() / "bench" / "results";
}

fs::path source_dir() { return fs::path(LOOM_SOURCE_DIR); }

fs::path data_file(const std::string& relative) {
  fs::path p = source_dir() / ".." / "shared" / "data" / relative;
  return fs::exists(p) ? p.lexically_normal() : fs::path();
}

}  // namespace loom::bench
