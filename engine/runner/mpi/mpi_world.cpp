// libloom_mpi.so: the MPI calls of an MPI run (see mpi_world.hpp).
#include "mpi/mpi_world.hpp"

#include <mpi.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <cstring>
#include <limits>
#include <thread>

#include "loom/error.hpp"
#include "loom/image.hpp"

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

void barrier() {
  MPI_Request request;
  MPI_Ibarrier(MPI_COMM_WORLD, &request);
  wait_for(request);
}

// The tiles of one rank, as rectangles of the image.
struct Rect {
  int x, y, w, h;
};
std::vector<Rect> tiles_of(int width, int height, const PixelRegion& r) {
  std::vector<Rect> rects;
  const int columns = (width + r.tile - 1) / r.tile, rows = (height + r.tile - 1) / r.tile;
  for (int t = r.part; t < columns * rows; t += r.parts) {
    const int x = (t % columns) * r.tile, y = (t / columns) * r.tile;
    rects.push_back({x, y, std::min(r.tile, width - x), std::min(r.tile, height - y)});
  }
  return rects;
}

std::int64_t pixels_in(const std::vector<Rect>& rects) {
  std::int64_t n = 0;
  for (const Rect& r : rects) n += std::int64_t(r.w) * r.h;
  return n;
}

// Copies the rows of each rectangle between the image and a packed buffer
// (tile after tile, row after row): `to_image` unpacks.
void copy_tiles(cv::Mat& image, const std::vector<Rect>& rects, float* packed, bool to_image) {
  const int channels = image.channels();
  for (const Rect& r : rects)
    for (int y = r.y; y < r.y + r.h; ++y) {
      float* row = image.ptr<float>(y) + std::size_t(r.x) * channels;
      const std::size_t n = std::size_t(r.w) * channels;
      if (to_image) std::memcpy(row, packed, n * sizeof(float));
      else std::memcpy(packed, row, n * sizeof(float));
      packed += n;
    }
}

class Split final : public PixelSplit {
 public:
  Split(std::string node, int tile, int rank, int size, bool by_samples)
      : node_(std::move(node)), tile_(tile), rank_(rank), size_(size), by_samples_(by_samples) {}

  PixelRegion region(const std::string& node) const override {
    return node == node_ ? PixelRegion{tile_, rank_, size_, by_samples_} : PixelRegion{};
  }

  void sum(double* values, std::size_t count) const override {
    barrier();  // the wait for the slowest rank, without polling; then the exchange, blocking
    constexpr std::size_t kChunk = std::size_t(1) << 28;  // MPI counts are ints
    for (std::size_t at = 0; at < count; at += kChunk) {
      const int n = int(std::min(kChunk, count - at));
      MPI_Reduce(rank_ == 0 ? MPI_IN_PLACE : values + at, values + at, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
      MPI_Bcast(values + at, n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    }
  }

  void combine(const std::string& node, const NodeSpec& spec, std::vector<Value>& outputs) const override {
    using Clock = std::chrono::steady_clock;
    const auto arrived = Clock::now();
    barrier();  // so that the time below is the exchange's, not the wait for the slowest rank
    const auto start = Clock::now();
    double megabytes = 0;
    for (std::size_t o = 0; o < outputs.size(); ++o) {
      if (spec.outputs[o].type != &type_of<Image>()) continue;
      const Image& part = outputs[o].as<Image>();
      megabytes += double(part.pixels.total() * part.pixels.elemSize()) / 1e6;
      outputs[o] = Value::make<Image>(Image(gather(part.pixels), part.encoding));  // `part` dies here
    }
    if (rank_ == 0)
      std::fprintf(stderr,
                   "mpi: %s: %.1f MB of images gathered from %d ranks in %.3f s (rank 0 waited %.3f s for the others)\n",
                   node.c_str(), megabytes, size_, std::chrono::duration<double>(Clock::now() - start).count(),
                   std::chrono::duration<double>(start - arrived).count());
  }

 private:
  // Every rank's tiles of `part`, gathered into the whole image on every rank.
  cv::Mat gather(const cv::Mat& part) const {
    const int channels = part.channels();
    std::vector<std::vector<Rect>> rects(static_cast<std::size_t>(size_));
    std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
    std::int64_t total = 0;
    for (int r = 0; r < size_; ++r) {
      rects[std::size_t(r)] = tiles_of(part.cols, part.rows, PixelRegion{tile_, r, size_});
      const std::int64_t n = pixels_in(rects[std::size_t(r)]);
      if (total + n > std::numeric_limits<int>::max())
        throw Error("image too large to gather over MPI (more than 2^31 pixels)");
      counts[std::size_t(r)] = int(n);
      offsets[std::size_t(r)] = int(total);
      total += n;
    }
    cv::Mat mine_image = part;  // a view: packing reads it
    std::vector<float> mine(std::size_t(counts[std::size_t(rank_)]) * channels);
    copy_tiles(mine_image, rects[std::size_t(rank_)], mine.data(), false);
    std::vector<float> all(std::size_t(total) * channels);
    MPI_Datatype pixel;  // one pixel's floats: counts stay in pixels, below 2^31
    MPI_Type_contiguous(channels, MPI_FLOAT, &pixel);
    MPI_Type_commit(&pixel);
    // Blocking: every rank is here already (the barrier in combine), and a
    // large exchange progresses only while MPI is polled.
    MPI_Allgatherv(mine.data(), counts[std::size_t(rank_)], pixel, all.data(), counts.data(), offsets.data(), pixel,
                   MPI_COMM_WORLD);
    MPI_Type_free(&pixel);
    cv::Mat whole(part.rows, part.cols, part.type());
    for (int r = 0; r < size_; ++r)
      copy_tiles(whole, rects[std::size_t(r)], all.data() + std::size_t(offsets[std::size_t(r)]) * channels, true);
    return whole;
  }

  std::string node_;
  int tile_, rank_, size_;
  bool by_samples_;
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
  std::unique_ptr<PixelSplit> split(const std::string& node, int tile, bool by_samples) override {
    return std::make_unique<Split>(node, tile, rank_, size_, by_samples);
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
