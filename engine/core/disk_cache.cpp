#include "loom/disk_cache.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "build_identity.hpp"
#include "loom/atomic_file.hpp"
#include "loom/error.hpp"
#include "loom/hash.hpp"
#include "loom/temporary_file.hpp"

namespace loom {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'L', 'O', 'O', 'M', 'C', 'A', 'C', 'H'};
constexpr std::uint32_t kFormatVersion = 2;  // 2: the four-lane payload checksum
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

bool is_hex(const std::string& s, std::size_t n) {
  if (s.size() != n) return false;
  for (char c : s)
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  return true;
}

// The cache's own files, and nothing else, are ever listed, counted or
// deleted: <dir>/<2 hex>/<16 hex starting with those 2>.loomcache (entries),
// and in those folders the staging files of write_file_atomic
// (".loomtmp-<pid>-<n>.loomcache") or of Loom before them
// (".<16 hex>.loomcache.tmp<pid>.<n>").
bool is_entry_name(const std::string& folder, const std::string& name) {
  const std::size_t ext = std::strlen(kExtension);
  return name.size() == 16 + ext && name.compare(16, ext, kExtension) == 0 && is_hex(name.substr(0, 16), 16) &&
         name.compare(0, 2, folder) == 0;
}
bool is_staging_file_name(const std::string& name) {
  if (is_staging_name(name)) return name.size() > std::strlen(kExtension) && name.find(kExtension) != std::string::npos;
  const std::string legacy = std::string(kExtension) + ".tmp";
  return name.size() > 17 + legacy.size() && name[0] == '.' && is_hex(name.substr(1, 16), 16) &&
         name.compare(17, legacy.size(), legacy) == 0;
}

enum class Kind { entry, staging };
struct OwnFile {
  fs::path path;
  Kind kind;
};

// Walks only the cache's layout: real folders named by 2 hex digits, and in
// them regular files (never links) with the cache's names.
std::vector<OwnFile> own_files(const fs::path& dir) {
  std::vector<OwnFile> files;
  std::error_code ec;
  for (fs::directory_iterator top(dir, ec), end; !ec && top != end; top.increment(ec)) {
    std::error_code e;
    const std::string folder = top->path().filename().string();
    if (!is_hex(folder, 2) || !fs::is_directory(top->symlink_status(e))) continue;
    for (fs::directory_iterator it(top->path(), e); !e && it != end; it.increment(e)) {
      std::error_code f;
      if (!fs::is_regular_file(it->symlink_status(f))) continue;
      const std::string name = it->path().filename().string();
      if (is_entry_name(folder, name)) files.push_back({it->path(), Kind::entry});
      else if (is_staging_file_name(name)) files.push_back({it->path(), Kind::staging});
    }
  }
  return files;
}

// The cache folder's tag (https://bford.info/cachedir/): marks it as Loom's,
// and tells backup tools to skip it.
constexpr const char* kTagName = "CACHEDIR.TAG";
constexpr const char* kTagText =
    "Signature: 8a477f597d28d172789f06886806bc55\n"
    "# This file is a cache directory tag created by Loom (loom run --cache).\n"
    "# For information about cache directory tags, see https://bford.info/cachedir/\n";

bool has_tag(const fs::path& dir) {
  std::ifstream in(dir / kTagName, std::ios::binary);
  std::string first(43, '\0');
  return in.read(first.data(), 43) && first == "Signature: 8a477f597d28d172789f06886806bc55";
}

// A folder Loom may use: missing, empty, tagged, or (a cache made before the
// tag) holding nothing but the cache's layout. Anything else is refused
// before a single file in it is touched.
void claim_folder(const fs::path& dir) {
  std::error_code ec;
  const auto status = fs::status(dir, ec);
  if (status.type() == fs::file_type::not_found) {
    fs::create_directories(dir, ec);
  } else if (!fs::is_directory(status) || has_tag(dir)) {
    return;  // a file or an unreadable path: stores fail quietly, as on a full disk
  } else {
    std::string stranger;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end && stranger.empty(); it.increment(ec)) {
      const std::string name = it->path().filename().string();
      std::error_code e;
      if (is_staging_name(name) || name == kTagName) continue;  // another process claiming it right now
      if (!is_hex(name, 2) || !fs::is_directory(it->symlink_status(e))) {
        stranger = name;
        break;
      }
      for (fs::directory_iterator f(it->path(), e); !e && f != end; f.increment(e)) {
        const std::string file = f->path().filename().string();
        std::error_code g;
        if (!fs::is_regular_file(f->symlink_status(g)) || (!is_entry_name(name, file) && !is_staging_file_name(file))) {
          stranger = name + "/" + file;
          break;
        }
      }
    }
    if (ec) return;  // unreadable: nothing will be stored or deleted there either
    if (!stranger.empty())
      throw Error("the cache folder " + dir.string() + " is not a Loom cache: it holds " + stranger +
                  " and no " + kTagName + ". Loom keeps its cache only in an empty folder or one of its own "
                  "(it deletes old entries); choose another --cache folder");
  }
  try {
    write_file_atomic(dir / kTagName, kTagText);
  } catch (const Error&) {
    // a read-only folder: nothing will be stored, so nothing needs the tag
  }
}
}  // namespace

// FNV-1a (Hasher's step) in four lanes over interleaved 8-byte words, the
// lanes and the tail then mixed by Hasher: four independent multiply chains
// instead of Hasher's one (docs/time.md has what that saves).
std::uint64_t DiskCache::checksum(const char* p, std::size_t n) {
  std::uint64_t lane[4] = {0x9e3779b97f4a7c15ull, 0xbf58476d1ce4e5b9ull, 0x94d049bb133111ebull, 0x100000001b3ull};
  std::size_t i = 0;
  for (; i + 32 <= n; i += 32)
    for (int k = 0; k < 4; ++k) {
      std::uint64_t w;
      std::memcpy(&w, p + i + 8 * k, 8);
      lane[k] = (lane[k] ^ w) * 0x100000001b3ull;
      lane[k] ^= lane[k] >> 29;
    }
  Hasher h;
  for (std::uint64_t l : lane) h.pod(l);
  return h.bytes(p + i, n - i).pod(static_cast<std::uint64_t>(n)).digest();
}

namespace {

// A cache entry mapped read-only: the page cache's own pages, so a read makes
// no buffer of its own (a fresh 48 MB buffer cost more than the disk, the
// checksum or the decoding: docs/time.md). Entries are replaced by rename,
// never rewritten in place, so the mapped file does not shrink under us.
class MappedEntry {
 public:
  explicit MappedEntry(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);  // a FIFO must not block
    if (fd < 0) return;
    struct stat st {};
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode)) {
      opened_ = true;
      if (st.st_size > 0) {
        void* p = ::mmap(nullptr, static_cast<std::size_t>(st.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
        if (p != MAP_FAILED) {
          data_ = static_cast<const char*>(p);
          size_ = static_cast<std::size_t>(st.st_size);
        }
      }
    }
    ::close(fd);
  }
  ~MappedEntry() {
    if (data_) ::munmap(const_cast<char*>(data_), size_);
  }
  MappedEntry(const MappedEntry&) = delete;
  MappedEntry& operator=(const MappedEntry&) = delete;

  bool opened() const { return opened_; }
  const char* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  bool opened_ = false;
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};


}  // namespace

DiskCache::DiskCache(Options options) : options_(std::move(options)), engine_build_(engine_build()) {
  claim_folder(options_.dir);
}

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
  const MappedEntry bytes(path);
  if (!bytes.opened()) return std::nullopt;
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
    const auto stored_checksum = header.pod<std::uint64_t>();
    if (bytes.size() != kHeaderBytes + size)
      return reject("is truncated (" + std::to_string(bytes.size()) + " bytes, expected " +
                    std::to_string(kHeaderBytes + size) + ")");
    const char* payload = bytes.data() + kHeaderBytes;
    if (checksum(payload, size) != stored_checksum) return reject("fails its checksum");
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

double DiskCache::expected_read_seconds(std::uint64_t bytes) const {
  return options_.read_entry_seconds + static_cast<double>(bytes) / (options_.read_mb_per_s * 1024 * 1024);
}

bool DiskCache::worth_storing(std::uint64_t bytes, double compute_seconds, int frames) const {
  const double n = std::max(frames, 1);
  return n * compute_seconds >= options_.min_seconds &&          // the run's time is worth files
         2 * expected_read_seconds(bytes) <= compute_seconds &&  // each frame reads back clearly faster
         n * static_cast<double>(bytes) <= options_.max_sequence_share * static_cast<double>(options_.max_bytes);
}

// One buffer: the header with its sizes and checksum patched in at the end.
std::uint64_t DiskCache::store(std::uint64_t key, const std::vector<Value>& values, double compute_seconds,
                               int frames) {
  if (!worth_storing(0, compute_seconds, frames)) return 0;  // too quick whatever the size
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
    if (!worth_storing(file.buffer().size(), compute_seconds, frames)) return 0;
    patch(kHeaderBytes - 16, payload);
    patch(kHeaderBytes - 8, checksum(file.buffer().data() + kHeaderBytes, payload));
    write_file_atomic(path_of(key), std::string_view(file.buffer().data(), file.buffer().size()));
    bytes_written_ += file.buffer().size();
    return file.buffer().size();
  } catch (const std::exception&) {
    return 0;
  }
}

DiskCache::Stats DiskCache::stats() const {
  Stats s;
  for (const OwnFile& f : own_files(options_.dir)) {
    std::error_code ec;
    const auto size = fs::file_size(f.path, ec);
    if (f.kind != Kind::entry || ec) continue;
    ++s.entries;
    s.bytes += size;
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
  for (const OwnFile& f : own_files(options_.dir)) {
    std::error_code e;
    const auto time = fs::last_write_time(f.path, e);
    if (f.kind == Kind::staging) {  // a writer killed before its rename
      if (!e && time < stale) fs::remove(f.path, e);
      continue;
    }
    const auto size = fs::file_size(f.path, e);
    if (e) continue;
    entries.push_back({f.path, time, size});
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
  for (const OwnFile& f : own_files(options_.dir)) fs::remove(f.path, ec);
}

}  // namespace loom
