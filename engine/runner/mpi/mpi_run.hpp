// `loom run` over MPI ranks, when mpirun or srun starts it: frames and sweep
// points dealt to the ranks (in blocks, or as they ask: --mpi-deal dynamic),
// or one image split into interleaved tiles of its pixel-independent nodes,
// gathered on rank 0 (on every rank when a node split later reads them);
// rank 0 runs the sinks that need the whole (docs/farm.md,
// docs/architecture.md). A plain `loom run` opens no MPI library: these calls
// then do what one process does.
#pragma once

#include <CLI/CLI.hpp>

#include "loom/evaluator.hpp"
#include "cli/run_settings.hpp"
#include "sweep/sweep.hpp"

namespace loom::runner {

class MpiWorld;

// --mpi-split and --mpi-tile, on `loom run`.
void add_mpi_options(CLI::App* run);

// Starts MPI when mpirun or srun started this process as one of several
// ranks. 0, or an exit code after saying why not: a `loom` built without MPI
// refuses (N copies would each do the whole run), as does --watch.
int start_mpi_if_launched(bool watch);
// The world, or null in a plain run.
MpiWorld* mpi_world();
int mpi_rank();  // 0 in a plain run

// session.evaluate(graph, options), or this rank's part of it. A node failing
// or a run cancelled on any rank ends every rank (MPI_Abort).
EvalResult evaluate_on_ranks(Session& session, const Graph& graph, const Registry& registry,
                             const EvalOptions& options);

// run_sweep, or the points dealt to the ranks (round-robin, or as they ask)
// and the tables written by rank 0.
int run_sweep_on_ranks(const SweepRequest& request, const RunSettings& settings);

}  // namespace loom::runner
