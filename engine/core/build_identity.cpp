#include "build_identity.hpp"

#include <elf.h>

#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "loom/hash.hpp"

namespace loom::detail {
namespace fs = std::filesystem;

namespace {

bool read_at(std::ifstream& in, std::uint64_t offset, void* data, std::size_t size) {
  in.seekg(static_cast<std::streamoff>(offset));
  in.read(static_cast<char*>(data), static_cast<std::streamsize>(size));
  return static_cast<std::size_t>(in.gcount()) == size;
}

// The descriptor of the NT_GNU_BUILD_ID note in a 64-bit ELF file's PT_NOTE
// segments (ELF gABI, "Note Section": name and descriptor padded to 4 bytes).
std::optional<std::string> gnu_build_id(std::ifstream& in) {
  Elf64_Ehdr eh{};
  if (!read_at(in, 0, &eh, sizeof eh) || std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 ||
      eh.e_ident[EI_CLASS] != ELFCLASS64 || eh.e_phentsize != sizeof(Elf64_Phdr))
    return std::nullopt;
  for (int i = 0; i < eh.e_phnum; ++i) {
    Elf64_Phdr ph{};
    if (!read_at(in, eh.e_phoff + static_cast<std::uint64_t>(i) * sizeof ph, &ph, sizeof ph)) return std::nullopt;
    if (ph.p_type != PT_NOTE || ph.p_filesz > (1u << 20)) continue;
    std::string notes(ph.p_filesz, '\0');
    if (!read_at(in, ph.p_offset, notes.data(), notes.size())) return std::nullopt;
    auto pad = [](std::size_t n) { return (n + 3) & ~std::size_t(3); };
    for (std::size_t at = 0; at + sizeof(Elf64_Nhdr) <= notes.size();) {
      Elf64_Nhdr nh{};
      std::memcpy(&nh, notes.data() + at, sizeof nh);
      const std::size_t name_at = at + sizeof nh, desc_at = name_at + pad(nh.n_namesz);
      if (desc_at + nh.n_descsz > notes.size()) break;
      if (nh.n_type == NT_GNU_BUILD_ID && nh.n_namesz == 4 && std::memcmp(notes.data() + name_at, "GNU", 4) == 0)
        return notes.substr(desc_at, nh.n_descsz);
      at = desc_at + pad(nh.n_descsz);
    }
  }
  return std::nullopt;
}

std::uint64_t identity_of(const fs::path& library) {
  std::ifstream in(library, std::ios::binary);
  if (!in) return 0;
  if (auto id = gnu_build_id(in)) return Hasher().str("gnu-build-id").str(*id).digest();
  in.clear();
  in.seekg(0);
  Hasher h;
  std::vector<char> block(1 << 20);
  while (in.read(block.data(), static_cast<std::streamsize>(block.size())) || in.gcount() > 0)
    h.bytes(block.data(), static_cast<std::size_t>(in.gcount()));
  return h.digest();
}

}  // namespace

std::uint64_t build_identity(const fs::path& library) {
  std::error_code ec;
  const auto size = fs::file_size(library, ec);
  const auto time = fs::last_write_time(library, ec).time_since_epoch().count();
  using Stamp = std::tuple<std::string, std::uintmax_t, std::int64_t>;
  static std::mutex mutex;
  static std::map<Stamp, std::uint64_t> known;
  const Stamp stamp{library.string(), ec ? 0 : size, static_cast<std::int64_t>(time)};
  {
    std::lock_guard lock(mutex);
    if (auto it = known.find(stamp); it != known.end()) return it->second;
  }
  const std::uint64_t id = identity_of(library);
  std::lock_guard lock(mutex);
  known[stamp] = id;
  return id;
}

}  // namespace loom::detail
