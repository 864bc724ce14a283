// Where a disk cache read goes. For image entries from one 640x360 RGB frame
// (2.6 MB) to a 2048² one (48 MB), all in the page cache (the disk is not
// touched, as on a rerun), each stage alone:
//   buffered_read  the old read: a fresh zero-filled buffer that ifstream fills
//   mapped_read    the new read: the entry mapped read-only (MAP_POPULATE)
//   checksum_1     the old checksum (Hasher: one FNV-1a chain)
//   checksum_4     the new checksum (DiskCache::checksum: four lanes)
//   decode         TypeTraits<Image>::read into a new image
// then DiskCache::load whole (the new path) beside the sum of the old stages.
// docs/time.md takes the storage rule's read rate from these figures.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>

#include "bench_harness.hpp"
#include "loom/disk_cache.hpp"
#include "loom/hash.hpp"
#include "loom/image.hpp"

namespace {

namespace fs = std::filesystem;

std::string buffered_read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  std::string bytes(static_cast<std::size_t>(in.tellg()), '\0');
  in.seekg(0);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return bytes;
}

char mapped_read(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  struct stat st {};
  ::fstat(fd, &st);
  const auto size = static_cast<std::size_t>(st.st_size);
  void* p = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
  ::close(fd);
  const char c = static_cast<const char*>(p)[size / 2];
  ::munmap(p, size);
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  loom::bench::Cli cli("bench_engine_cache_read",
                       "Disk cache reads by stage (buffer or mapping, checksum, decoding) against entry size.");
  bool quick = false;
  cli.quick(quick, "two sizes");
  cli.parse(argc, argv);
  const fs::path dir = fs::temp_directory_path() / ("loom-bench-cache-read-" + std::to_string(::getpid()));
  loom::DiskCache::Options o;
  o.dir = dir;
  loom::DiskCache cache(o);
  std::printf("load average %.1f\n", loom::bench::load_average());

  loom::bench::Csv csv("engine_cache_read_stages",
                       {"image", "megabytes", "buffered_read_s", "mapped_read_s", "checksum_1_s", "checksum_4_s",
                        "decode_s", "old_path_s", "load_s", "load_mb_per_s", "load_average"});
  std::vector<std::pair<int, int>> sizes = {{640, 360}, {1280, 720}, {1920, 1080}, {2048, 2048}};
  if (quick) sizes = {{640, 360}, {1920, 1080}};
  std::uint64_t key = 1;
  volatile std::uint64_t sink = 0;
  for (const auto& [w, h] : sizes) {
    const loom::Image image(cv::Mat(h, w, CV_32FC3, cv::Scalar(0.25, 0.5, 0.75)), loom::Encoding::linear);
    const loom::Value value = loom::Value::make(image);
    if (cache.store(key, {value}) == 0) return 1;
    fs::path file;
    for (const auto& e : fs::recursive_directory_iterator(dir))
      if (e.is_regular_file() && e.path().extension() == ".loomcache") file = e.path();  // the one entry
    const std::string bytes = buffered_read(file);
    const double mb = static_cast<double>(bytes.size()) / (1024 * 1024);
    loom::ByteWriter encoded;
    loom::TypeTraits<loom::Image>::write(image, encoded);
    const auto& payload = encoded.buffer();

    const auto buffered = loom::bench::time_median([&] { sink = sink + buffered_read(file).size(); }, 7);
    const auto mapped = loom::bench::time_median([&] { sink = sink + mapped_read(file); }, 7);
    const auto one_lane =
        loom::bench::time_median([&] { sink = sink + loom::Hasher().bytes(bytes.data(), bytes.size()).digest(); }, 7);
    const auto four_lanes =
        loom::bench::time_median([&] { sink = sink + loom::DiskCache::checksum(bytes.data(), bytes.size()); }, 7);
    const auto decode = loom::bench::time_median([&] {
      loom::ByteReader r(payload.data(), payload.size());
      sink = sink + static_cast<std::uint64_t>(loom::TypeTraits<loom::Image>::read(r).width());
    }, 7);
    const auto load = loom::bench::time_median([&] {
      if (!cache.load(key)) std::exit(1);
    }, 7);
    const double old_path = buffered.median + one_lane.median + decode.median;
    csv.row({std::to_string(w) + "x" + std::to_string(h), mb, buffered.median, mapped.median, one_lane.median,
             four_lanes.median, decode.median, old_path, load.median, mb / load.median,
             loom::bench::load_average()});
    fs::remove(file);
    ++key;
  }
  csv.save();
  loom::bench::plot(csv, {"megabytes", "load_s", "", "Disk cache: read time of one image entry", true, true, ""});
  fs::remove_all(dir);
  return 0;
}
