#include "sweep/sweep_axes.hpp"

#include <cmath>
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
    const double v = log ? std::exp(std::log(a) + t * (std::log(b) - std::log(a))) : a + t * (b - a);
    if (integer) values.emplace_back(static_cast<long long>(std::llround(v)));
    else values.emplace_back(v);
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

std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, bool zip) {
  std::vector<SweepPoint> points;
  if (axes.empty()) return points;
  std::size_t count = zip ? axes[0].values.size() : 1;
  for (const auto& a : axes) {
    if (zip && a.values.size() != count)
      throw Error("--zip: every --sweep needs as many values (" + axes[0].input + " has " +
                  std::to_string(count) + ", " + a.input + " has " + std::to_string(a.values.size()) + ")");
    if (!zip) count *= a.values.size();
  }
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
