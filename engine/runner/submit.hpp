// `loom submit` and `loom jobs`: a graph's frames, sweep points and
// simulations as tasks in a job folder (job_folder.hpp), run by Slurm or by
// the local dispatcher (dispatch.hpp). See docs/farm.md.
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
