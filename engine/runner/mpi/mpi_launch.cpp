// Whether mpirun or srun started this `loom`, and starting MPI if so.
#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "mpi/mpi_run.hpp"
#include "mpi/mpi_settings.hpp"
#include "mpi/mpi_world.hpp"

namespace loom::runner {
namespace {

std::unique_ptr<MpiWorld> g_world;

// The number of ranks the launcher started, from its environment: Open MPI's
// mpirun, PMI (MPICH's hydra, srun --mpi=pmi2), or srun --mpi=pmix. 0 when no
// launcher started this process. A Slurm batch script's own process (a farm
// task) has none of the PMI variables, so it stays a plain run.
int launched_ranks() {
  auto number = [](const char* name) {
    const char* v = std::getenv(name);
    return v ? std::atoi(v) : 0;
  };
  if (int n = number("OMPI_COMM_WORLD_SIZE")) return n;
  if (int n = number("PMI_SIZE")) return n;
  if (std::getenv("PMIX_RANK")) return number("SLURM_STEP_NUM_TASKS");
  return 0;
}

std::filesystem::path mpi_library() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return exe.parent_path().parent_path() / "lib" / "libloom_mpi.so";
}

}  // namespace

MpiSettings& mpi_settings() {
  static MpiSettings settings;
  return settings;
}

void add_mpi_options(CLI::App* run) {
  MpiSettings& s = mpi_settings();
  run->add_option("--mpi-split", s.split,
                  "under mpirun/srun: how ranks share the run: auto (frames or sweep points when there are "
                  "several, else tiles), frames, tiles, samples (tiles, but a path tracer's samples split instead)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "frames", "tiles", "samples"}));
  run->add_option("--mpi-tile", s.tile, "under mpirun/srun: tile edge in pixels when an image is split")
      ->capture_default_str()
      ->check(CLI::Range(1, 16384));
  run->add_option("--mpi-deal", s.deal,
                  "under mpirun/srun: static (rank r takes the r-th block of frames, every N-th sweep point "
                  "from r, the tiles t mod N = r, the samples s mod N = r) or dynamic (frames, points or tiles "
                  "in at most 16 parts a rank, sample passes in 256 slots, each rank taking the next as it "
                  "finishes one: for ranks of uneven speed)")
      ->capture_default_str()
      ->check(CLI::IsMember({"static", "dynamic"}));
}

int start_mpi_if_launched(bool watch) {
  const int ranks = launched_ranks();
  if (ranks <= 1) return 0;
#ifndef LOOM_WITH_MPI
  (void)watch;
  std::cerr << "error: loom was started by mpirun or srun as one of " << ranks
            << " ranks, but this loom was built without MPI: each rank would do the whole run. Install "
               "libopenmpi-dev (scripts/install-deps) and build again, or run loom without mpirun\n";
  return kInvalid;
#else
  if (watch) {
    std::cerr << "error: --watch cannot run under mpirun or srun\n";
    return kInvalid;
  }
  const std::filesystem::path library = mpi_library();
  void* handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_GLOBAL);  // GLOBAL: Open MPI's components need libmpi's symbols
  auto entry = handle ? reinterpret_cast<LoomMpiWorldEntry>(::dlsym(handle, "loom_mpi_world")) : nullptr;
  if (!entry) {
    std::cerr << "error: started by mpirun or srun, but " << library.string() << " cannot be loaded: "
              << (handle ? "no loom_mpi_world in it" : ::dlerror()) << "\n";
    return kInvalid;
  }
  std::string error;
  g_world.reset(entry(&error));
  if (!g_world) {
    std::cerr << "error: MPI did not start: " << error << "\n";
    return kInvalid;
  }
  return 0;
#endif
}

MpiWorld* mpi_world() { return g_world.get(); }
int mpi_rank() { return g_world ? g_world->rank() : 0; }

}  // namespace loom::runner
