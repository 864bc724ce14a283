#include "sweep/sweep_axes.hpp"

#include <climits>
#include <cmath>
#include <cstdlib>
#include <regex>

#include "loom/error.hpp"

namespace loom::runner {

namespace {

// Splits at commas outside brackets, braces and strings: "[1,2],[3,4]" is two values.
std::vector<std::string> split_values(const std::string& text) {
  std::vector<std::string> parts(1);
  int depth = 0;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted && c == '\\' && i + 1 < text.size()) {
      parts.back() += {c, text[++i]};
      continue;
    }
    if (c == '"') quoted = !quoted;
    if (!quoted && (c == '[' || c == '{')) ++depth;
    if (!quoted && (c == ']' || c == '}')) --depth;
    if (!quoted && depth == 0 && c == ',') parts.emplace_back();
    else parts.back() += c;
  }
  return parts;
}

// A:B:N or A:B:N:log; empty when `text` is not a range.
std::vector<json> range_values(const std::string& spec, const std::string& text, bool integer) {
  static const std::regex range(R"(^\s*([-+0-9.eE]+):([-+0-9.eE]+):([0-9]+)(:log)?\s*$)");
  std::smatch m;
  if (!std::regex_match(text, m, range)) return {};
  double a = 0, b = 0;
  try {
    a = std::stod(m[1]);
    b = std::stod(m[2]);
  } catch (const std::exception&) {
    throw Error("--sweep " + spec + ": range bounds must be numbers (A:B:N or A:B:N:log)");
  }
  const long n = std::stol(m[3]);
  const bool log = m[4].matched;
  if (n < 1 || n > 100000) throw Error("--sweep " + spec + ": a range has 1 to 100000 values, not " + m[3].str());
  if (log && (a <= 0 || b <= 0)) throw Error("--sweep " + spec + ": a :log range needs bounds above 0");
  std::vector<json> values;
  for (long i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    // a (1 - t) + b t, not a + t (b - a): b - a overflows for bounds near the largest double.
    const double v = log ? std::exp(std::log(a) * (1 - t) + std::log(b) * t) : a * (1 - t) + b * t;
    if (!std::isfinite(v))
      throw Error("--sweep " + spec + ": value " + std::to_string(i + 1) + " of the range is not a finite number "
                  "(bounds up to about 1e308)");
    if (!integer) {
      values.emplace_back(v);
      continue;
    }
    if (std::abs(v) > INT_MAX)
      throw Error("--sweep " + spec + ": " + json(v).dump() + " is beyond what an Int input holds (" +
                  std::to_string(-INT_MAX) + " to " + std::to_string(INT_MAX) + ")");
    values.emplace_back(static_cast<long long>(std::llround(v)));
  }
  return values;
}

}  // namespace

SweepAxis parse_sweep_axis(const std::string& spec, const GraphView& view) {
  const std::size_t eq = spec.find('=');
  if (eq == std::string::npos || !parse_link(spec.substr(0, eq)))
    throw Error("--sweep " + spec + ": expected ID.INPUT=V1,V2,... or ID.INPUT=A:B:N[:log]");
  ResolvedInput input;
  try {
    input = view.input(spec.substr(0, eq));
  } catch (const Error& e) {
    throw Error("--sweep " + spec + ": " + e.what());
  }
  SweepAxis axis{spec.substr(0, eq), {}};
  const std::string text = spec.substr(eq + 1);
  axis.values = range_values(spec, text, input.spec.type && input.spec.type->name == "Int");
  if (axis.values.empty())
    for (const std::string& part : split_values(text)) {
      if (part.empty()) throw Error("--sweep " + spec + ": an empty value in the list");
      json v = json::parse(part, nullptr, false);
      axis.values.push_back(v.is_discarded() ? json(part) : v);  // not JSON: a string, as --set
    }
  return axis;
}

std::size_t max_sweep_points() {
  const char* text = std::getenv("LOOM_MAX_SWEEP_POINTS");
  if (!text || !*text) return kMaxSweepPoints;
  char* end = nullptr;
  const unsigned long long n = std::strtoull(text, &end, 10);
  if (*end != '\0' || n == 0 || text[0] == '-')
    throw Error(std::string("LOOM_MAX_SWEEP_POINTS=") + text + ": expected a whole number of points above 0");
  return static_cast<std::size_t>(n);
}

std::size_t count_sweep_points(const std::vector<SweepAxis>& axes, bool zip) {
  if (axes.empty()) return 0;
  std::size_t count = zip ? axes[0].values.size() : 1;
  std::string product;
  bool wrapped = false;  // four axes of 65,536 values wrapped the count to 0 ("0 points", exit 0)
  for (const auto& a : axes) {
    if (zip && a.values.size() != count)
      throw Error("--zip: every --sweep needs as many values (" + axes[0].input + " has " +
                  std::to_string(count) + ", " + a.input + " has " + std::to_string(a.values.size()) + ")");
    if (zip) continue;
    product += (product.empty() ? "" : " × ") + std::to_string(a.values.size());
    wrapped = wrapped || __builtin_mul_overflow(count, a.values.size(), &count);
  }
  const std::size_t limit = max_sweep_points();
  if (wrapped || count > limit)
    throw Error("--sweep: " + product + " = " + (wrapped ? std::string("more than 2^64") : std::to_string(count)) +
                " points is more than the limit of " + std::to_string(limit) + " (every point's graph is built and "
                "checked before any runs): sweep fewer values, use --zip, or raise the limit with "
                "LOOM_MAX_SWEEP_POINTS=N");
  return count;
}

std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, bool zip) {
  std::vector<SweepPoint> points;
  if (axes.empty()) return points;
  const std::size_t count = count_sweep_points(axes, zip);
  points.reserve(count);
  for (std::size_t p = 0; p < count; ++p) {
    SweepPoint point{{}, json::object()};
    std::size_t rest = p;
    for (std::size_t k = axes.size(); k-- > 0;) {  // the last axis varies fastest
      const auto& a = axes[k];
      const json& v = a.values[zip ? p : rest % a.values.size()];
      if (!zip) rest /= a.values.size();
      point.values[a.input] = v;
      point.assignments.insert(point.assignments.begin(), a.input + "=" + v.dump());
    }
    points.push_back(std::move(point));
  }
  return points;
}

}  // namespace loom::runner
