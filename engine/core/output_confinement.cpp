#include "output_confinement.hpp"

#include "loom/error.hpp"

namespace loom::detail {
namespace fs = std::filesystem;

namespace {

constexpr int kMaxLinkDepth = 40;  // as Linux's ELOOP limit

fs::path resolve(const fs::path& path, int depth) {
  if (depth > kMaxLinkDepth) throw Error("more than 40 symbolic links in a chain at " + path.string());
  fs::path done = path.root_path();
  const fs::path relative = path.relative_path();
  for (auto it = relative.begin(); it != relative.end(); ++it) {
    const fs::path next = done / *it;
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(next, ec);
    if (ec || st.type() == fs::file_type::not_found) {
      for (auto rest = it; rest != relative.end(); ++rest) done /= *rest;  // not there yet
      return done.lexically_normal();
    }
    if (fs::is_symlink(st)) {
      fs::path target = fs::read_symlink(next, ec);
      if (ec) throw Error("cannot read the symbolic link " + next.string() + ": " + ec.message());
      if (target.is_relative()) target = done / target;
      done = resolve(target.lexically_normal(), depth + 1);
    } else {
      done = next;
    }
  }
  return done.lexically_normal();
}

bool is_within(const fs::path& path, const fs::path& folder) {
  const fs::path rel = path.lexically_relative(folder);
  return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

fs::path real_path_of(const fs::path& path) { return resolve(path.lexically_normal(), 0); }

void require_inside_real_output(const fs::path& resolved, const fs::path& output_dir, const std::string& written) {
  const fs::path root = real_path_of(fs::absolute(output_dir));
  const fs::path real = real_path_of(fs::absolute(resolved));
  if (is_within(real, root)) return;
  throw Error("output path \"" + written + "\" leads out of the output folder through a symbolic link (it is " +
              real.string() + "): run with --allow-outside-out to write there");
}

}  // namespace loom::detail
