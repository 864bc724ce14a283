#include "vdb_file.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

#include "loom/atomic_file.hpp"
#include "loom/error.hpp"
#include "loom/hash.hpp"
#include "loom/temporary_file.hpp"

namespace loom::volume {
namespace {

// An OpenVDB file starts: magic (8 bytes), file version, library major and
// minor (4 each), "has grid offsets" (1), then the UUID as 36 characters.
constexpr std::size_t kUuidOffset = 21, kUuidLength = 36;

// A UUID (version-5-like layout, 8-4-4-4-12 hex digits) from two hashes.
std::string uuid_of(std::uint64_t a, std::uint64_t b) {
  char text[kUuidLength + 1];
  std::snprintf(text, sizeof text, "%08x-%04x-5%03x-%04x-%012llx", static_cast<unsigned>(a >> 32),
                static_cast<unsigned>((a >> 16) & 0xffff), static_cast<unsigned>(a & 0xfff),
                static_cast<unsigned>(0x8000 | ((b >> 48) & 0x3fff)),
                static_cast<unsigned long long>(b & 0xffffffffffffull));
  return text;
}

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw Error("cannot read back " + path.string());
  return bytes;
}

}  // namespace

void write_vdb(const Volume& volume, const std::filesystem::path& path,
               const std::vector<std::pair<std::string, std::string>>& metadata) {
  // Registers the grid types for writing; idempotent, with a lock of its own
  // (inside std::call_once it crashed: OpenVDB's own call_once nested in it).
  openvdb::initialize();
  openvdb::GridCPtrVec grids{volume.density};
  if (volume.velocity) grids.push_back(volume.velocity);
  openvdb::MetaMap meta;
  for (const auto& [key, value] : metadata) meta.insertMeta(key, openvdb::StringMetadata(value));
  std::filesystem::create_directories(path.parent_path().empty() ? "." : path.parent_path());
  // OpenVDB writes to a named file only: stage it, then fix the UUID.
  TemporaryFile staging(path, ".vdb");
  try {
    openvdb::io::File file(staging.path().string());
    file.write(grids, meta);
    file.close();
  } catch (const openvdb::Exception& e) {
    throw Error("cannot write " + path.string() + ": " + e.what());
  }
  std::string bytes = read_bytes(staging.path());
  if (bytes.size() < kUuidOffset + kUuidLength) throw Error("OpenVDB wrote a truncated " + path.string());
  const std::string_view rest(bytes.data() + kUuidOffset + kUuidLength, bytes.size() - kUuidOffset - kUuidLength);
  const std::uint64_t a = Hasher().str(rest).digest(), b = Hasher(a).str(rest).digest();
  bytes.replace(kUuidOffset, kUuidLength, uuid_of(a, b));
  staging.discard();
  write_file_atomic(path, bytes);
}

}  // namespace loom::volume
