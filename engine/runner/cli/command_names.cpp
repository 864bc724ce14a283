#include "cli/command_names.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include "loom/suggest.hpp"

namespace loom::runner {

std::optional<std::string> unknown_command_message(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-' || argv[1][0] == '\0') return std::nullopt;
  const std::string given = argv[1];
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == given) return std::nullopt;
    names.push_back(sub->get_name());
  }
  std::string text = "unknown command \"" + given + "\"";
  const auto near = near_names(given, names, 1);
  if (!near.empty()) text += ": did you mean \"" + near.front() + "\"?";
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return text + " (commands: " + list + "; loom --help for more)";
}

void refuse_options_as_values(CLI::App& app) {
  std::set<std::string> names;
  for (const CLI::Option* opt : app.get_options()) {
    for (const auto& n : opt->get_lnames()) names.insert("--" + n);
    for (const auto& n : opt->get_snames()) names.insert("-" + n);
  }
  for (CLI::Option* opt : app.get_options()) {
    if (!opt->nonpositional() || opt->get_expected_max() == 0) continue;  // positionals and flags
    const std::string option = opt->get_name();
    opt->check(CLI::Validator(
        [names, option](std::string& value) -> std::string {
          if (!names.count(value.substr(0, value.find('=')))) return {};
          return "needs a value before \"" + value + "\", which is an option (write: " + option + " VALUE " + value +
                 ")";
        },
        "", "not an option"));
  }
  for (CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) refuse_options_as_values(*sub);
}

namespace {

// Numbers of at least `bound` (above it if `strict`), whole ones if `whole`.
CLI::Validator number_check(double bound, bool whole, bool strict) {
  std::ostringstream b;
  b << bound;
  const std::string wanted =
      std::string(whole ? "a whole number" : "a number") + (strict ? " above " : " of at least ") + b.str();
  return CLI::Validator(
      [=](std::string& value) -> std::string {
        std::size_t used = 0;
        double v = NAN;
        try {
          v = std::stod(value, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        const bool in_range = strict ? v > bound : v >= bound;
        const bool ok = used == value.size() && std::isfinite(v) && in_range && (!whole || v == std::floor(v));
        return ok ? std::string() : "expected " + wanted + ", got \"" + value + "\"";
      },
      "", wanted);
}

}  // namespace

CLI::Validator whole_number_at_least(long least) { return number_check(static_cast<double>(least), true, false); }
CLI::Validator number_at_least(double least) { return number_check(least, false, false); }
CLI::Validator number_above(double bound) { return number_check(bound, false, true); }

}  // namespace loom::runner
