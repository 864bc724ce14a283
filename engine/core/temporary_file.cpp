#include "loom/temporary_file.hpp"

#include <atomic>
#include <cctype>
#include <climits>
#include <cstdio>
#include <cstring>
#include <random>

#include <unistd.h>

#include "loom/error.hpp"

namespace loom {
namespace fs = std::filesystem;

namespace {

// The live staging paths, in fixed storage a signal handler may read. A slot
// is free (0), being written (1) or live (2); `generation` changes whenever a
// slot is reused, so the handler never unlinks a path torn by a concurrent
// writer.
constexpr int kSlots = 256;
struct Slot {
  std::atomic<int> state{0};
  std::atomic<unsigned> generation{0};
  char path[PATH_MAX];
};
Slot g_slots[kSlots];

int claim_slot(const fs::path& path) {
  const std::string& text = path.native();
  if (text.size() >= PATH_MAX) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1)) continue;
    g_slots[i].generation.fetch_add(1);
    std::memcpy(g_slots[i].path, text.c_str(), text.size() + 1);
    g_slots[i].state.store(2);
    return i;
  }
  return -1;  // more than kSlots staging files at once: the destructor still removes it
}

void release_slot(int slot) {
  if (slot >= 0) g_slots[slot].state.store(0);
}

std::string extension_for(const std::string& extension) {
  // A long or odd extension is not needed for staging; only a short one is kept.
  if (extension.size() > 16 || extension.find('/') != std::string::npos) return {};
  return extension;
}

// Drawn once per process: two processes of one pid — on two machines, or in
// two PID namespaces — writing into one shared folder never stage under one
// name (a pid alone let one rename the other's bytes into place).
const std::string& process_nonce() {
  static const std::string nonce = [] {
    std::random_device device;
    char hex[17];
    std::snprintf(hex, sizeof hex, "%08x%08x", device(), device());
    return std::string(hex);
  }();
  return nonce;
}

}  // namespace

TemporaryFile::TemporaryFile(fs::path target, const std::string& extension) : target_(std::move(target)) {
  static std::atomic<unsigned> counter{0};
  path_ = target_.parent_path() / (".loomtmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
                                   process_nonce() + extension_for(extension));
  slot_ = claim_slot(path_);
}

TemporaryFile::~TemporaryFile() { discard(); }

void TemporaryFile::discard() noexcept {
  if (done_) return;
  done_ = true;
  ::unlink(path_.c_str());
  release_slot(slot_);
}

void TemporaryFile::commit() {
  std::error_code ec;
  fs::rename(path_, target_, ec);
  if (ec) {
    discard();
    throw Error("cannot write " + target_.string() + ": " + ec.message());
  }
  done_ = true;
  release_slot(slot_);
}

bool is_staging_name(const std::string& name) {
  const std::string prefix = ".loomtmp-";
  if (name.rfind(prefix, 0) != 0) return false;
  std::size_t i = prefix.size(), digits = 0;
  while (i < name.size() && name[i] >= '0' && name[i] <= '9') ++i, ++digits;
  if (digits == 0 || i >= name.size() || name[i] != '-') return false;
  std::size_t counter_digits = 0;
  for (++i; i < name.size() && name[i] >= '0' && name[i] <= '9'; ++i) ++counter_digits;
  if (counter_digits == 0) return false;
  if (i < name.size() && name[i] == '-') {  // the process's nonce (older staging names have none)
    std::size_t hex = 0;
    for (++i; i < name.size() && std::isxdigit(static_cast<unsigned char>(name[i])); ++i) ++hex;
    if (hex == 0) return false;
  }
  return i == name.size() || name[i] == '.';
}

void remove_temporary_files() noexcept {
  char copy[PATH_MAX];
  for (Slot& s : g_slots) {
    if (s.state.load() != 2) continue;
    const unsigned generation = s.generation.load();
    std::memcpy(copy, s.path, sizeof copy);
    copy[PATH_MAX - 1] = '\0';
    if (s.state.load() == 2 && s.generation.load() == generation) ::unlink(copy);
  }
}

}  // namespace loom
