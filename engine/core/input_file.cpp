#include "loom/input_file.hpp"

#include "loom/error.hpp"
#include "loom/suggest.hpp"

namespace loom {

namespace fs = std::filesystem;

namespace {

// `; did you mean "a" or "b"?` for the entries of `folder` near `name`.
std::string near_entries(const fs::path& folder, const std::string& name) {
  std::vector<std::string> entries;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    entries.push_back(it->path().filename().string());
  const auto near = near_names(name, entries);
  std::string text;
  for (std::size_t i = 0; i < near.size(); ++i)
    text += (i == 0 ? "; did you mean \"" : i + 1 == near.size() ? " or \"" : ", \"") + near[i] + "\"";
  return near.empty() ? text : text + "?";
}

// The note on how the path was found, when it lies under the graph's folder.
std::string resolution_note(const fs::path& path, const fs::path& graph_dir) {
  if (graph_dir.empty()) return "";
  const fs::path rel = path.lexically_normal().lexically_relative(graph_dir.lexically_normal());
  if (rel.empty() || *rel.begin() == "..") return "";
  return " (a relative path is resolved against the graph file's folder, " + graph_dir.lexically_normal().string() +
         ")";
}

}  // namespace

void require_input_file(const fs::path& path, const std::string& what, const fs::path& graph_dir) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::regular) return;
  const std::string head = "cannot read " + what + " " + path.string() + ": ";
  const fs::path folder = path.parent_path();
  switch (st.type()) {
    case fs::file_type::directory: throw Error(head + "it is a folder, not a file" + resolution_note(path, graph_dir));
    case fs::file_type::fifo: throw Error(head + "it is a FIFO (named pipe), not a regular file");
    case fs::file_type::socket: throw Error(head + "it is a socket, not a regular file");
    case fs::file_type::block:
    case fs::file_type::character: throw Error(head + "it is a device, not a regular file");
    case fs::file_type::not_found: break;
    default: throw Error(head + (ec ? ec.message() : std::string("not a regular file")));
  }
  if (!folder.empty() && !fs::is_directory(folder, ec))
    throw Error(head + "no such folder " + folder.string() +
                near_entries(folder.parent_path(), folder.filename().string()) + resolution_note(path, graph_dir));
  throw Error(head + "no such file" + near_entries(folder.empty() ? fs::path(".") : folder,
                                                   path.filename().string()) +
              resolution_note(path, graph_dir));
}

std::string not_a_regular_file(const fs::path& path) {
  std::error_code ec;
  switch (fs::status(path, ec).type()) {
    case fs::file_type::directory: return "a directory";
    case fs::file_type::fifo: return "a FIFO (named pipe)";
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::socket: return "a socket";
    default: return "";
  }
}

}  // namespace loom
