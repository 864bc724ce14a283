#include "loom/formats/regular_file.hpp"

#include "loom/error.hpp"

namespace loom::formats {
namespace fs = std::filesystem;

namespace {

std::string why_not_regular(const fs::file_status& st, const std::error_code& ec) {
  switch (st.type()) {
    case fs::file_type::not_found: return "no such file";
    case fs::file_type::directory: return "it is a folder, not a file";
    case fs::file_type::fifo: return "it is a FIFO (named pipe), not a regular file";
    case fs::file_type::socket: return "it is a socket, not a regular file";
    case fs::file_type::block:
    case fs::file_type::character: return "it is a device, not a regular file";
    default: return ec ? ec.message() : std::string("not a regular file");
  }
}

}  // namespace

void require_regular_file(const fs::path& path, const std::string& what) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() != fs::file_type::regular)
    throw Error("cannot read " + what + " " + path.string() + ": " + why_not_regular(st, ec));
}

}  // namespace loom::formats
