// The MPI calls of an MPI run, behind an interface without <mpi.h>: they live
// in libloom_mpi.so (mpi_world.cpp), which `loom` opens only when mpirun or
// srun started it (mpi_launch.cpp), so a plain run never loads libmpi.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "loom/evaluator.hpp"

namespace loom::runner {

// Which ranks receive a split node's whole images.
enum class Gather { to_rank_0, to_every_rank };

// Items 0..count-1 (a split node's parts of tiles, frames, sweep points)
// handed out as ranks ask, so that a slower rank takes fewer. The items are
// cut into at most 16 parts per rank, each a run of consecutive items (one
// item each when there are no more): a rank that runs out waits for at most
// one part of a slower rank, 1/16 of its share, and an ask costs something
// only every 1/16 of a share (dealing 480 frames of 1-3 ms one at a time took
// 2.5 ms a frame more than blocks). Rank r's first part is part r, then each
// next() takes the next part from a counter on rank 0 (MPI_Fetch_and_op on
// a window; rank 0 need not be waiting for the ask: shared memory and
// InfiniBand answer alone, but over TCP Open MPI answers only while rank 0
// is inside MPI, which answer() is for). Made by every rank at once; its end
// is a barrier (without polling) then MPI_Win_free.
class Dealer {
 public:
  struct Part {
    long begin = 0, end = 0;  // items [begin, end); empty when none is left
    bool empty() const { return begin >= end; }
  };
  virtual ~Dealer() = default;
  // The next part this rank takes.
  virtual Part next() = 0;
  // Lets MPI answer the other ranks' asks (rank 0, while it works).
  virtual void answer() = 0;
  // Every rank calls it once it has no part left; rank 0 prints how many
  // items each rank took: "mpi: WHAT dealt as ranks asked: 10, 9, 5 to ranks 0..2".
  virtual void report(const std::string& what) = 0;
};

// A split node's PixelSplit over the ranks. report() is called by every rank
// right after the node's evaluation, before any other MPI call (it ends rank
// 0's thread that answers the others' asks). Split by samples, it has rank 0
// print how many samples each rank took and its time in them: "mpi: trace:
// samples dealt as ranks asked in 16 passes: 1.1M, 1.2M, 0.6M to ranks 0..2
// (busy 5.1, 5.0, 5.2 s of 5.4 s)".
class RankSplit : public PixelSplit {
 public:
  virtual void report() const = 0;
};

class MpiWorld {
 public:
  virtual ~MpiWorld() = default;  // MPI_Finalize
  virtual int rank() const = 0;
  virtual int size() const = 0;
  virtual std::string library() const = 0;  // MPI_Get_library_version's first line
  virtual void barrier() = 0;
  virtual int max_over_ranks(int value) = 0;
  virtual int min_over_ranks(int value) = 0;
  // Every rank's value, by rank.
  virtual std::vector<double> gather_all(double value) = 0;
  // Ends the job: every rank, with this exit code (MPI_Abort).
  [[noreturn]] virtual void abort(int exit_code) = 0;
  // Items 0..count-1 dealt as ranks ask (Dealer); every rank calls it at once.
  virtual std::unique_ptr<Dealer> dealer(long count) = 0;
  // A PixelSplit for `node`: this rank computes the interleaved tiles
  // t % size == rank of tile x tile pixels; combine() gathers every rank's
  // tiles of each Image output into the whole image on the ranks `gather`
  // names, in place (the other ranks keep their part: their results must
  // then not be stored, nor read by anything they evaluate later). `dealt`:
  // the tiles are cut into 16 parts per rank (t % parts == part), each rank
  // takes its next part as it finishes one (combine() hands it over; the
  // engine runs the node again on it), so a slower rank computes fewer. By
  // samples: this rank takes the samples s % size == rank of every pixel and
  // sum() adds the node's sums over the ranks (reduced on rank 0, then
  // broadcast, so that every rank holds the very same doubles); by samples
  // and `dealt`, every pass is cut into slots (PixelRegion::slots) that the
  // ranks take as they ask (take_slot), a faster rank taking more.
  virtual std::unique_ptr<RankSplit> split(const std::string& node, int tile, bool by_samples, Gather gather,
                                           bool dealt) = 0;
};

}  // namespace loom::runner

// libloom_mpi.so's entry point, `loom_mpi_world`: calls MPI_Init_thread and
// returns the world, or null with *error set when MPI cannot start.
using LoomMpiWorldEntry = loom::runner::MpiWorld* (*)(std::string* error);
