// The `submit` and `jobs` subcommands of `loom`, registered by main.cpp.
#pragma once

#include <memory>

#include <CLI/CLI.hpp>

namespace loom::runner {

class FarmCommands {
 public:
  virtual ~FarmCommands() = default;
  virtual bool chosen() const = 0;  // `submit` or `jobs` was given
  virtual int run() = 0;
};

std::unique_ptr<FarmCommands> add_farm_commands(CLI::App& app);

}  // namespace loom::runner
