#include "loom/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <memory>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "loom/error.hpp"
#include "loom/temporary_file.hpp"

namespace loom {
namespace fs = std::filesystem;

namespace {

void create_parent(const fs::path& path) {
  if (!path.has_parent_path()) return;
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec) throw Error("cannot create folder " + path.parent_path().string() + ": " + ec.message());
}

// Every byte written, flushed to the disk and closed, each step checked: a
// full disk or a quota shows here, not later as a cut file.
void write_staging(const TemporaryFile& tmp, std::string_view bytes) {
  auto fail = [&](int error) {
    throw Error("cannot write " + tmp.target().string() + ": " + std::strerror(error ? error : EIO));
  };
  // O_TRUNC, not O_EXCL: a staging file of a killed process whose pid came
  // back may hold this name. O_NOFOLLOW: a link planted there is not followed.
  const int fd = ::open(tmp.path().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) fail(errno);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : ENOSPC;
      ::close(fd);
      fail(error);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    fail(error);
  }
  if (::close(fd) != 0) fail(errno);
}

}  // namespace

void write_file_atomic(const fs::path& path, std::string_view bytes) {
  create_parent(path);
  TemporaryFile tmp(path, path.extension().string());
  write_staging(tmp, bytes);
  tmp.commit();
}

void write_files_atomic(const std::vector<std::pair<fs::path, std::string>>& files) {
  std::vector<std::unique_ptr<TemporaryFile>> staged;
  for (const auto& [path, bytes] : files) {
    create_parent(path);
    staged.push_back(std::make_unique<TemporaryFile>(path, path.extension().string()));
    write_staging(*staged.back(), bytes);
  }
  std::size_t renamed = 0;
  try {
    for (; renamed < staged.size(); ++renamed) staged[renamed]->commit();
  } catch (...) {
    std::error_code ec;
    for (std::size_t i = 0; i < renamed; ++i) fs::remove(staged[i]->target(), ec);
    throw;
  }
}

}  // namespace loom
