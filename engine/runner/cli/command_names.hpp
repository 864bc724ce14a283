// Command-line mistakes named as such: `loom rnu` (a mistyped command, named
// with the nearest one instead of CLI11's "A subcommand is required") and
// `loom run g.json --profile --quiet` (an option given as another's value),
// `--jobs 0` (a number out of range, said in words).
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace loom::runner {

// The error for argv[1] when it is neither an option nor one of app's
// subcommands: "unknown command "rnu": did you mean "run"? (commands: ...)".
std::optional<std::string> unknown_command_message(const CLI::App& app, int argc, char** argv);

// CLI11 hands an option that needs a value the next word even when that word is
// another option: `--profile --quiet` wrote the profile to a file named
// "--quiet" and did not apply --quiet. Every option of app and of its
// subcommands that takes a value refuses one naming an option of its own
// command ("--quiet", "-q", "--out=DIR"), with an error that says so. Call once
// every option is added.
void refuse_options_as_values(CLI::App& app);

// Checks for numeric options: "--jobs: expected a whole number of at least 1,
// got 0" where CLI11's PositiveNumber said "Value 0 not in range 0.000000 to
// 1797693134862315708...".
CLI::Validator whole_number_at_least(long least);
CLI::Validator number_at_least(double least);
CLI::Validator number_above(double bound);

}  // namespace loom::runner
