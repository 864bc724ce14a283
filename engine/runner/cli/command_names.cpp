#include "cli/command_names.hpp"

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

}  // namespace loom::runner
