// libloom_mpi.so: the MPI calls of an MPI run (see mpi_world.hpp).
#include "mpi/mpi_world.hpp"

#include <mpi.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <optional>
#include <thread>

#include "loom/image.hpp"
#include "mpi/mpi_samples.hpp"
#include "mpi/mpi_tiles.hpp"

namespace loom::runner {
namespace {

// Waits for a non-blocking call, sleeping between tests. MPI's blocking calls
// poll without sleeping: a rank waiting for a slower one would take cores
// from it wherever ranks share cores (measured on 2 cores: 2 ranks x 1 thread
// took 2.6 times as long as 1 rank x 2 threads, polling).
void wait_for(MPI_Request& request) {
  for (int done = 0; MPI_Test(&request, &done, MPI_STATUS_IGNORE), !done;)
    std::this_thread::sleep_for(std::chrono::microseconds(200));
}

// Waits for an exchange that every rank has started. The tiles are not
// contiguous, so MPI copies them through shared memory in 32-kB fragments, a
// few in flight at a time (the sender packs one while the receiver unpacks
// another): both ranks must run at once. Where ranks share cores, a blocking
// wait polls while the peer waits for a time slice; yielding between polls
// hands the core over (this exchange of 99.5 MB over 2 ranks, alone, at load
// 6 on 2 cores: 0.03-0.11 s yielding, 0.06-0.73 s blocking, 0.12-0.24 s
// sleeping 20 us between polls; docs/farm.md).
void exchange_all(std::vector<MPI_Request>& requests) {
  for (int done = 0; MPI_Testall(int(requests.size()), requests.data(), &done, MPI_STATUSES_IGNORE), !done;)
    sched_yield();
}

// Any call into MPI progresses a window's traffic: over TCP, rank 0 answers
// the others' asks of a SharedCounter only inside one.
void answer_asks() {
  int flag = 0;
  MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
}

void barrier() {
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  wait_for(request);
}

// The most parts per rank a Dealer cuts its items into (mpi_world.hpp).
constexpr long kDealtPartsPerRank = 16;

// A number on rank 0 that every rank takes the next value of (an MPI window:
// over shared memory or UCX it answers by itself; over TCP only within one
// of rank 0's MPI calls, so rank 0 answers from a thread while dealt work
// runs: Split::start_answering, and for frames evaluate_answering). Every rank
// makes and destroys it at once.
class SharedCounter {
 public:
  explicit SharedCounter(long first) {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    // Open MPI 4.1's osc/rdma, its default between nodes, fails to make a
    // window over TCP (MPI_ERR_WIN; open-mpi/ompi#9871): said, not a crash.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    const int made =
        MPI_Win_allocate(rank_ == 0 ? sizeof(long) : 0, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD, &next_, &window_);
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
    if (made != MPI_SUCCESS) {
      if (rank_ == 0)
        std::fputs("loom: --mpi-deal dynamic needs an MPI window on rank 0 that every rank can reach, and MPI "
                   "could not make one (Open MPI over TCP between nodes: run with OMPI_MCA_osc=sm,pt2pt set; "
                   "docs/farm.md)\n",
                   stderr);
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
    if (rank_ == 0) *next_ = first;
    MPI_Barrier(MPI_COMM_WORLD);
  }
  ~SharedCounter() {
    barrier();  // MPI_Win_free would poll while a slower rank works
    MPI_Win_free(&window_);
  }
  SharedCounter(const SharedCounter&) = delete;
  SharedCounter& operator=(const SharedCounter&) = delete;

  // The counter's value, which goes up by one.
  long take() {
    const long one = 1;
    long value = -1;
    const auto asked = std::chrono::steady_clock::now();
    MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window_);
    MPI_Fetch_and_op(&one, &value, MPI_LONG, 0, 0, MPI_SUM, window_);
    MPI_Win_unlock(0, window_);
    const std::chrono::duration<double> waited = std::chrono::steady_clock::now() - asked;
    longest_wait_ = std::max(longest_wait_, waited.count());
    return value;
  }
  double longest_wait() const { return longest_wait_; }  // seconds, the longest of this rank's takes

 private:
  int rank_ = 0;
  long* next_ = nullptr;
  MPI_Win window_ = MPI_WIN_NULL;
  double longest_wait_ = 0;
};

// Parts 0..size-1 are every rank's first, taken without asking.
class CounterDealer final : public Dealer {
 public:
  CounterDealer(long count, int rank, int size)
      : count_(count), parts_(std::min(count, kDealtPartsPerRank * size)), rank_(rank), size_(size), next_(size) {}

  Part next() override {
    long part = -1;
    if (!asked_) {
      part = rank_;
      asked_ = true;
    } else if (!done_) {
      part = next_.take();
    }
    done_ = done_ || part >= parts_;
    if (done_) return {};
    const Part items{count_ * part / parts_, count_ * (part + 1) / parts_};
    taken_ += items.end - items.begin;
    return items;
  }

  void answer() override { answer_asks(); }

  void report(const std::string& what) override {
    const double mine[2] = {double(taken_), next_.longest_wait()};
    std::vector<double> all(2 * std::size_t(size_), 0);
    MPI_Request request;
    MPI_Igather(mine, 2, MPI_DOUBLE, all.data(), 2, MPI_DOUBLE, 0, MPI_COMM_WORLD, &request);
    wait_for(request);
    if (rank_ != 0) return;
    std::string counts;
    double longest = 0;
    for (int r = 0; r < size_; ++r) {
      counts += (counts.empty() ? "" : ", ") + std::to_string(long(all[2 * std::size_t(r)]));
      longest = std::max(longest, all[2 * std::size_t(r) + 1]);
    }
    std::fprintf(stderr, "mpi: %s dealt as ranks asked: %s to ranks 0..%d (the longest wait for an answer: %.3f s)\n",
                 what.c_str(), counts.c_str(), size_ - 1, longest);
  }

 private:
  long count_, parts_;
  int rank_, size_;
  long taken_ = 0;  // items this rank took
  bool asked_ = false, done_ = false;
  SharedCounter next_;  // the next part to deal
};

class Split final : public RankSplit {
  using Clock = std::chrono::steady_clock;

 public:
  Split(std::string node, int tile, int rank, int size, bool by_samples, Gather gather, bool dealt)
      : node_(std::move(node)),
        tile_(tile),
        rank_(rank),
        size_(size),
        by_samples_(by_samples),
        gather_(gather),
        parts_(dealt && !by_samples ? size * kDealtPartsPerRank : size),
        part_(rank),
        samples_(size, by_samples && dealt) {
    if (dealt && by_samples) slot_counter_ = std::make_unique<SharedCounter>(0);
    if (dealt && !by_samples) {  // the dealer's items are the parts (16 a rank: one item a part)
      dealer_ = std::make_unique<CounterDealer>(parts_, rank_, size_);
      part_ = int(dealer_->next().begin);  // this rank's own first part
    }
  }

  ~Split() override { stop_answering(); }

  // The node asks for its region as it starts: by samples, its first pass's time begins.
  PixelRegion region(const std::string& node) const override {
    if (node != node_) return PixelRegion{};
    if ((slot_counter_ || dealer_) && rank_ == 0 && !answering_.joinable()) start_answering();
    if (by_samples_ && !started_) started_ = resumed_ = Clock::now();
    return PixelRegion{tile_, part_, parts_, by_samples_, samples_.slots()};
  }

  // Dealt by samples: the counter's next number, as a slot of this pass. One
  // number past the pass's slots per rank and pass (then no more asks).
  int take_slot() const override {
    if (!slot_counter_ || pass_taken_) return -1;
    const std::lock_guard lock(mpi_);
    const long fetched = slot_counter_->take();
    next_number_ = fetched + 1;
    const int slot = samples_.slot(fetched);
    pass_taken_ = slot < 0;
    return slot;
  }

  // Every rank's samples, busy time and, dealt, the counter's number it got
  // to travel beside the sums (an allgather of three doubles a rank), so that
  // every rank starts the next pass's slots at the same number (SampleShares).
  void sum(double* values, std::size_t count, double work) const override {
    const double busy = std::chrono::duration<double>(Clock::now() - resumed_.value_or(Clock::now())).count();
    const std::lock_guard lock(mpi_);
    barrier();  // the wait for the slowest rank, without polling; then the exchange, blocking
    const double mine[3] = {work, busy, double(std::max(next_number_, samples_.base()))};
    std::vector<double> all(3 * std::size_t(size_));
    MPI_Allgather(mine, 3, MPI_DOUBLE, all.data(), 3, MPI_DOUBLE, MPI_COMM_WORLD);
    constexpr std::size_t kChunk = std::size_t(1) << 28;  // MPI counts are ints
    for (std::size_t at = 0; at < count; at += kChunk) {
      const int n = int(std::min(kChunk, count - at));
      MPI_Reduce(rank_ == 0 ? MPI_IN_PLACE : values + at, values + at, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
      MPI_Bcast(values + at, n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    }
    const std::size_t ranks = all.size() / 3;
    std::vector<double> taken(ranks), seconds(ranks), next(ranks);
    for (std::size_t r = 0; r < ranks; ++r) {
      taken[r] = all[3 * r];
      seconds[r] = all[3 * r + 1];
      next[r] = all[3 * r + 2];
    }
    samples_.passed(taken, seconds, next);
    pass_taken_ = false;
    resumed_ = Clock::now();
  }

  void report() const override {
    stop_answering();
    if (!by_samples_ || rank_ != 0 || samples_.passes() == 0) return;  // none summed: interrupted or failed
    const double seconds = std::chrono::duration<double>(resumed_.value_or(*started_) - *started_).count();
    std::fputs(samples_.report(node_, seconds).c_str(), stderr);
  }

  // Dealt: keeps the part's tiles and takes the next part, if any is left
  // (the engine then runs the node on it). Then, or at once when the split
  // is static, every image output's tiles go to the ranks that receive (rank
  // 0, or every rank), all the messages in flight at once; a receiving
  // rank's image becomes the whole, the others keep their parts.
  void combine(const std::string& node, const NodeSpec& spec, std::vector<Value>& outputs) const override {
    const std::lock_guard lock(mpi_);
    if (dealer_ && keep_and_take_next(spec, outputs)) return;
    const auto arrived = Clock::now();
    barrier();  // so that the time below is the exchange's, not the wait for the slowest rank
    const auto start = Clock::now();
    const std::vector<int> owner = owners();
    std::vector<std::pair<std::size_t, cv::Mat>> images;  // kept until every message is done
    std::vector<MPI_Request> requests;
    double megabytes = 0;
    for (std::size_t o = 0, kept = 0; o < outputs.size(); ++o) {
      if (spec.outputs[o].type != &type_of<Image>()) continue;
      const cv::Mat& part = outputs[o].as<Image>().pixels;
      megabytes += double(part.total() * part.elemSize()) / 1e6;
      images.emplace_back(o, dealer_ ? kept_[kept++] : receives(rank_) ? writable_pixels(outputs[o]) : part);
      exchange(images.back().second, owner, requests);
    }
    // Every rank is here already (the barrier): polled without sleeping, since
    // the exchange progresses only while MPI is polled, but yielding the core
    // between polls (see exchange_all).
    exchange_all(requests);
    for (auto& [o, pixels] : images) outputs[o] = Value::make<Image>(outputs[o].as<Image>().like(std::move(pixels)));
    kept_.clear();
    if (dealer_) dealer_->report(node + ": " + std::to_string(parts_) + " parts");
    if (rank_ != 0) return;
    std::fprintf(stderr,
                 "mpi: %s: %.1f MB of images gathered from %d ranks to %s in %.3f s (rank 0 waited %.3f s "
                 "for the others)\n",
                 node.c_str(), megabytes, size_, gather_ == Gather::to_every_rank ? "every rank" : "rank 0",
                 std::chrono::duration<double>(Clock::now() - start).count(),
                 std::chrono::duration<double>(start - arrived).count());
  }

 private:
  bool receives(int rank) const { return gather_ == Gather::to_every_rank || rank == 0; }

  // Rank 0, dealt: over TCP, Open MPI answers another rank's ask of the
  // counter only inside one of rank 0's MPI calls, and rank 0 makes one a
  // slot or a part (on three nodes, ranks 1 and 2 took 9 % and 11 % of the
  // samples; of tiles, rank 0 worked 2.9 s and the others 0.7-0.8 s). A
  // thread calls in every millisecond while the node runs, as rank 0 does
  // for frames (docs/farm.md); MPI_THREAD_SERIALIZED: the split's calls on
  // rank 0 hold mpi_.
  void start_answering() const {
    answering_on_ = true;
    answering_ = std::thread([this] {
      while (answering_on_) {
        {
          const std::lock_guard lock(mpi_);
          answer_asks();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
  }
  void stop_answering() const {
    answering_on_ = false;
    if (answering_.joinable()) answering_.join();
  }

  // Dealt: this part's tiles kept (the first part's images become the ones
  // kept), and the next part taken. False when none is left.
  bool keep_and_take_next(const NodeSpec& spec, std::vector<Value>& outputs) const {
    for (std::size_t o = 0, kept = 0; o < outputs.size(); ++o) {
      if (spec.outputs[o].type != &type_of<Image>()) continue;
      if (kept == kept_.size()) kept_.push_back(writable_pixels(outputs[o]));
      else copy_part(outputs[o].as<Image>().pixels, kept_[kept], tile_, part_, parts_);
      ++kept;
    }
    mine_.push_back(part_);
    const Dealer::Part next = dealer_->next();
    if (next.empty()) return false;
    part_ = int(next.begin);
    return true;
  }

  // The rank that computed each part: every rank's own, or as dealt.
  std::vector<int> owners() const {
    std::vector<int> owner(std::size_t(parts_), -1);
    if (!dealer_) {
      for (int p = 0; p < parts_; ++p) owner[std::size_t(p)] = p;
      return owner;
    }
    for (int p : mine_) owner[std::size_t(p)] = rank_;
    MPI_Allreduce(MPI_IN_PLACE, owner.data(), parts_, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return owner;
  }

  // Posts the tiles of this rank's parts of `image` to every rank that
  // receives and, if this one does, every other rank's parts into it (the
  // message's tag is the part). In strips of rows of at most 1 GB, so that no
  // message nears MPI's 2^31-byte limits.
  void exchange(cv::Mat& image, const std::vector<int>& owner, std::vector<MPI_Request>& requests) const {
    const int strip = int(std::max<std::size_t>(1, (std::size_t(1) << 30) / image.step));
    for (int y0 = 0; y0 < image.rows; y0 += strip) {
      const int y1 = std::min(image.rows, y0 + strip);
      for (int p = 0; p < parts_; ++p) {
        const int from = owner[std::size_t(p)];
        if (from != rank_ && !receives(rank_)) continue;
        MPI_Datatype tiles = tiles_type(image, y0, y1, tile_, p, parts_);
        for (int r = 0; r < size_; ++r) {
          if (from == rank_ && r != rank_ && receives(r))
            MPI_Isend(image.data, 1, tiles, r, p, MPI_COMM_WORLD, &requests.emplace_back());
          else if (from != rank_ && r == from)
            MPI_Irecv(image.data, 1, tiles, r, p, MPI_COMM_WORLD, &requests.emplace_back());
        }
        MPI_Type_free(&tiles);  // MPI keeps it until the messages using it are done
      }
    }
  }

  std::string node_;
  int tile_, rank_, size_;
  bool by_samples_;
  Gather gather_;
  int parts_;
  // Dealt: the state of the dealing, changed by combine() (const in PixelSplit).
  mutable int part_;                   // the part the node computes now
  std::unique_ptr<Dealer> dealer_;     // dealt: hands out the parts
  mutable std::vector<int> mine_;      // the parts this rank computed
  mutable std::vector<cv::Mat> kept_;  // their tiles, one image per Image output
  // By samples: what the ranks took, and when this rank's pass began; dealt,
  // the counter of slots, and whether this rank was told the pass is taken.
  mutable SampleShares samples_;
  std::unique_ptr<SharedCounter> slot_counter_;
  mutable long next_number_ = 0;
  mutable bool pass_taken_ = false;
  mutable std::mutex mpi_;  // rank 0: held by each of the split's MPI calls while answering_ runs
  mutable std::thread answering_;
  mutable std::atomic<bool> answering_on_{false};
  mutable std::optional<Clock::time_point> started_, resumed_;
};

class World final : public MpiWorld {
 public:
  World() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~World() override { MPI_Finalize(); }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::string library() const override {
    char text[MPI_MAX_LIBRARY_VERSION_STRING];
    int length = 0;
    MPI_Get_library_version(text, &length);
    std::string s(text, std::size_t(length));
    return s.substr(0, s.find_first_of("\n,"));
  }
  void barrier() override { loom::runner::barrier(); }
  int max_over_ranks(int value) override { return reduce(value, MPI_MAX); }
  int min_over_ranks(int value) override { return reduce(value, MPI_MIN); }
  std::vector<double> gather_all(double value) override {
    std::vector<double> all(static_cast<std::size_t>(size_));
    MPI_Request request;
    MPI_Iallgather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, MPI_COMM_WORLD, &request);
    wait_for(request);
    return all;
  }
  [[noreturn]] void abort(int exit_code) override {
    MPI_Abort(MPI_COMM_WORLD, exit_code);
    std::_Exit(exit_code);  // MPI_Abort does not return; this says so to the compiler
  }
  std::unique_ptr<Dealer> dealer(long count) override { return std::make_unique<CounterDealer>(count, rank_, size_); }
  std::unique_ptr<RankSplit> split(const std::string& node, int tile, bool by_samples, Gather gather,
                                   bool dealt) override {
    return std::make_unique<Split>(node, tile, rank_, size_, by_samples, gather, dealt);
  }

 private:
  int reduce(int value, MPI_Op op) {
    int result = value;
    MPI_Request request;
    MPI_Iallreduce(&value, &result, 1, MPI_INT, op, MPI_COMM_WORLD, &request);
    wait_for(request);
    return result;
  }
  int rank_ = 0, size_ = 1;
};

}  // namespace
}  // namespace loom::runner

// Combine runs on an evaluation's worker thread while the main thread waits
// in evaluate(): MPI calls come from one thread at a time (SERIALIZED).
extern "C" __attribute__((visibility("default"))) loom::runner::MpiWorld* loom_mpi_world(std::string* error) {
  int provided = 0;
  if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS) {
    *error = "MPI_Init_thread failed";
    return nullptr;
  }
  if (provided < MPI_THREAD_SERIALIZED) {
    *error = "this MPI library does not allow calls from several threads (MPI_THREAD_SERIALIZED)";
    MPI_Finalize();
    return nullptr;
  }
  return new loom::runner::World();
}
