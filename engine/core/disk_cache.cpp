#include "loom/disk_cache.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <dlfcn.h>

#include "build_identity.hpp"
#include "loom/atomic_file.hpp"
#include "loom/hash.hpp"

namespace loom {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'L', 'O', 'O', 'M', 'C', 'A', 'C', 'H'};
constexpr std::uint32_t kFormatVersion = 1;
constexpr const char* kExtension = ".loomcache";
// magic, format version, key, value count, payload size, payload checksum
constexpr std::size_t kHeaderBytes = 8 + 4 + 8 + 4 + 8 + 8;

// libloom's own file: the engine's build enters every key.
std::uint64_t engine_build() {
  Dl_info info{};
  if (::dladdr(reinterpret_cast<void*>(&engine_build), &info) && info.dli_fname)
    return detail::build_identity(info.dli_fname);
  return 0;
}

std::string hex(std::uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

bool is_entry(const fs::path& p) { return p.extension() == kExtension; }
bool is_temporary(const fs::path& p) { return p.filename().string().rfind('.', 0) == 0; }

}  // namespace

DiskCache::DiskCache(Options options) : options_(std::move(options)), engine_build_(engine_build()) {}

fs::path DiskCache::default_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "loom";
  if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "loom";
  return fs::temp_directory_path() / "loom-cache";
}

std::uint64_t DiskCache::key(std::uint64_t computation_hash, std::uint64_t plugin_build) const {
  return Hasher().pod(computation_hash).pod(plugin_build).pod(engine_build_).digest();
}

fs::path DiskCache::path_of(std::uint64_t key) const {
  const std::string name = hex(key);
  return options_.dir / name.substr(0, 2) / (name + kExtension);
}

bool DiskCache::contains(std::uint64_t key) const {
  std::error_code ec;
  return fs::is_regular_file(path_of(key), ec);
}

std::optional<std::vector<Value>> DiskCache::load(std::uint64_t key, std::string* problem) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path path = path_of(key);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return std::nullopt;
  const auto file_size = static_cast<std::size_t>(std::max<std::streamoff>(0, in.tellg()));
  std::string bytes(file_size, '\0');
  in.seekg(0);
  in.read(bytes.data(), static_cast<std::streamsize>(file_size));
  if (static_cast<std::size_t>(in.gcount()) != file_size) bytes.resize(static_cast<std::size_t>(in.gcount()));
  in.close();
  auto reject = [&](const std::string& why) -> std::optional<std::vector<Value>> {
    std::error_code ec;
    fs::remove(path, ec);
    if (problem) *problem = "cache entry " + path.string() + " " + why + ": deleted, recomputing";
    return std::nullopt;
  };
  try {
    ByteReader header(bytes.data(), std::min(bytes.size(), kHeaderBytes));
    char magic[8];
    header.bytes(magic, sizeof magic);
    if (std::memcmp(magic, kMagic, sizeof magic) != 0) return reject("is not a Loom cache entry");
    if (header.pod<std::uint32_t>() != kFormatVersion) return reject("has another format version");
    if (header.pod<std::uint64_t>() != key) return reject("belongs to another key");
    const auto count = header.pod<std::uint32_t>();
    const auto size = header.pod<std::uint64_t>();
    const auto checksum = header.pod<std::uint64_t>();
    if (bytes.size() != kHeaderBytes + size)
      return reject("is truncated (" + std::to_string(bytes.size()) + " bytes, expected " +
                    std::to_string(kHeaderBytes + size) + ")");
    const char* payload = bytes.data() + kHeaderBytes;
    if (Hasher().bytes(payload, size).digest() != checksum) return reject("fails its checksum");
    std::vector<Value> values;
    std::size_t offset = 0;
    for (std::uint32_t i = 0; i < count; ++i) {
      ByteReader r(payload + offset, size - offset);
      const std::string type_name = r.str();
      const auto version = r.pod<std::int32_t>();
      const auto value_size = r.pod<std::uint64_t>();
      if (value_size > r.remaining()) return reject("is truncated");
      const TypeInfo* type = find_type(type_name);
      if (!type || !type->storable()) return std::nullopt;  // its plugin is not loaded: a miss
      if (version != type->serial_version) return reject("holds " + type_name + " of an older format");
      offset += (size - offset) - r.remaining();
      ByteReader vr(payload + offset, value_size);
      auto data = type->read(vr);
      if (!vr.at_end()) return reject("has bytes past its " + type_name);
      offset += value_size;
      values.emplace_back(type, std::move(data));
    }
    if (offset != size) return reject("has bytes past its values");
    std::error_code ec;
    fs::last_write_time(path, fs::file_time_type::clock::now(), ec);  // least recently used
    bytes_read_ += bytes.size();
    read_nanoseconds_ += static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
    return values;
  } catch (const std::exception& e) {
    return reject(std::string("cannot be read (") + e.what() + ")");
  }
}

// One buffer: the header with its sizes and checksum patched in at the end.
std::uint64_t DiskCache::store(std::uint64_t key, const std::vector<Value>& values, double compute_seconds) {
  if (compute_seconds < options_.min_seconds) return 0;
  for (const Value& v : values)
    if (!v || !v.type()->storable()) return 0;
  try {
    ByteWriter file;
    file.bytes(kMagic, sizeof kMagic);
    file.pod<std::uint32_t>(kFormatVersion);
    file.pod<std::uint64_t>(key);
    file.pod<std::uint32_t>(static_cast<std::uint32_t>(values.size()));
    file.pod<std::uint64_t>(0);  // payload size, patched below
    file.pod<std::uint64_t>(0);  // payload checksum, patched below
    auto patch = [&file](std::size_t at, std::uint64_t v) { std::memcpy(file.buffer().data() + at, &v, sizeof v); };
    for (const Value& v : values) {
      file.str(v.type()->name);
      file.pod<std::int32_t>(v.type()->serial_version);
      const std::size_t size_at = file.buffer().size();
      file.pod<std::uint64_t>(0);
      v.type()->write(v.data(), file);
      patch(size_at, file.buffer().size() - size_at - sizeof(std::uint64_t));
    }
    const std::size_t payload = file.buffer().size() - kHeaderBytes;
    const double read_seconds = static_cast<double>(file.buffer().size()) / (options_.read_mb_per_s * 1024 * 1024);
    if (2 * read_seconds > compute_seconds) return 0;  // cheaper to compute again
    patch(kHeaderBytes - 16, payload);
    patch(kHeaderBytes - 8, Hasher().bytes(file.buffer().data() + kHeaderBytes, payload).digest());
    write_file_atomic(path_of(key), std::string_view(file.buffer().data(), file.buffer().size()));
    bytes_written_ += file.buffer().size();
    return file.buffer().size();
  } catch (const std::exception&) {
    return 0;
  }
}

DiskCache::Stats DiskCache::stats() const {
  Stats s;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(options_.dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec) || !is_entry(it->path()) || is_temporary(it->path())) continue;
    ++s.entries;
    s.bytes += it->file_size(ec);
  }
  return s;
}

void DiskCache::trim() {
  struct Entry {
    fs::path path;
    fs::file_time_type time;
    std::uint64_t size;
  };
  std::vector<Entry> entries;
  std::uint64_t total = 0;
  const auto stale = fs::file_time_type::clock::now() - std::chrono::hours(1);
  std::error_code ec;
  for (fs::recursive_directory_iterator it(options_.dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e;
    if (!it->is_regular_file(e)) continue;
    const auto time = it->last_write_time(e);
    if (is_temporary(it->path())) {  // a writer killed before its rename
      if (!e && time < stale) fs::remove(it->path(), e);
      continue;
    }
    if (!is_entry(it->path())) continue;
    const auto size = it->file_size(e);
    if (e) continue;
    entries.push_back({it->path(), time, size});
    total += size;
  }
  if (total <= options_.max_bytes) return;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.time < b.time; });
  for (const Entry& e : entries) {
    if (total <= options_.max_bytes) break;
    std::error_code rm;
    fs::remove(e.path, rm);  // another process may have removed it already
    total -= e.size;
  }
}

void DiskCache::clear() {
  std::error_code ec;
  std::vector<fs::path> doomed;
  for (fs::recursive_directory_iterator it(options_.dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec) && (is_entry(it->path()) || is_temporary(it->path()))) doomed.push_back(it->path());
  for (const auto& p : doomed) fs::remove(p, ec);
}

}  // namespace loom
