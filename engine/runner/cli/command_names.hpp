// `loom rnu`: a mistyped command is named, with the nearest command, instead
// of CLI11's "A subcommand is required".
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace loom::runner {

// The error for argv[1] when it is neither an option nor one of app's
// subcommands: "unknown command "rnu": did you mean "run"? (commands: ...)".
std::optional<std::string> unknown_command_message(const CLI::App& app, int argc, char** argv);

}  // namespace loom::runner
