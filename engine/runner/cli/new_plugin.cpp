#include "cli/new_plugin.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "cli/exit_codes.hpp"
#include "loom/atomic_file.hpp"
#include "loom/error.hpp"
#include "loom/plugin_loader.hpp"

namespace loom::runner {

namespace fs = std::filesystem;

namespace {

fs::path executable_prefix() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path().parent_path().lexically_normal();
}

// Plugin names become library names (libloom_NAME.so) and C identifiers.
bool valid_plugin_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || !std::islower(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name)
    if (!(std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'))
      return false;
  return true;
}

std::string substitute(std::string text, const std::vector<std::pair<std::string, std::string>>& tokens) {
  for (const auto& [token, value] : tokens)
    for (std::size_t at = text.find(token); at != std::string::npos; at = text.find(token, at + value.size()))
      text.replace(at, token.size(), value);
  return text;
}

// A template file's name in the scaffold: "x.cpp.in" -> "x.cpp", "gitignore.in" -> ".gitignore".
fs::path output_name(const fs::path& relative) {
  fs::path out = relative;
  if (out.extension() == ".in") out.replace_extension();
  if (out == "gitignore") out = ".gitignore";
  return out;
}

}  // namespace

fs::path plugin_template_dir() { return executable_prefix() / "share" / "loom" / "templates" / "plugin"; }

std::string scaffold_node_name(const std::string& plugin) {
  std::string node;
  bool upper = true;
  for (char c : plugin) {
    if (c == '_') {
      upper = true;
      continue;
    }
    node += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return node + "Exposure";
}

int new_plugin(const std::string& name, const fs::path& dir) {
  if (!valid_plugin_name(name)) {
    std::cerr << "error: plugin name \"" << name
              << "\" must start with a lowercase letter and hold only a-z, 0-9 and _ "
                 "(it names libloom_NAME.so)\n";
    return kInvalid;
  }
  // A plugin of the same name on the path would shadow the new one, or be shadowed.
  loom::Registry registry;
  const loom::PluginLoader loader(registry);
  for (const auto& p : loader.plugins())
    if (p.name == name) {
      std::cerr << "error: a plugin named \"" << name << "\" is already on the plugin path ("
                << p.library.string() << "): choose another name\n";
      return kInvalid;
    }
  const fs::path templates = plugin_template_dir();
  std::error_code ec;
  if (!fs::is_directory(templates, ec)) {
    std::cerr << "error: plugin templates not found in " << templates.string()
              << " (this loom's install is incomplete: reinstall Loom)\n";
    return kInvalid;
  }
  const fs::path target = fs::absolute(dir / name).lexically_normal();
  if (fs::exists(target, ec) && !(fs::is_directory(target, ec) && fs::is_empty(target, ec))) {
    std::cerr << "error: " << target.string() << " already exists and is not an empty folder: "
              << "choose another name or --dir\n";
    return kInvalid;
  }

  // The Loom this command belongs to, for find_package(loom) and the README.
  const fs::path prefix = executable_prefix();
  const bool installed = fs::exists(prefix / "lib" / "cmake" / "loom" / "loomTargets.cmake", ec);
  const std::vector<std::pair<std::string, std::string>> tokens = {
      {"{{name}}", name}, {"{{Node}}", scaffold_node_name(name)}, {"{{prefix}}", prefix.string()}};

  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(templates))
    if (entry.is_regular_file()) files.push_back(fs::relative(entry.path(), templates));
  std::sort(files.begin(), files.end());
  try {
    for (const fs::path& relative : files) {
      std::ifstream in(templates / relative, std::ios::binary);
      std::stringstream text;
      text << in.rdbuf();
      if (!in) throw Error("cannot read template " + (templates / relative).string());
      write_file_atomic(target / output_name(relative), substitute(text.str(), tokens));
    }
  } catch (const Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kInvalid;
  }

  std::cout << "wrote plugin \"" << name << "\" (node " << scaffold_node_name(name) << ") in "
            << target.string() << ":\n";
  for (const fs::path& relative : files) std::cout << "  " << output_name(relative).string() << "\n";
  std::cout << "\nnext, in " << target.string() << ":\n"
            << "  cmake -S . -B build -DCMAKE_PREFIX_PATH=" << prefix.string() << " && cmake --build build\n"
            << "  ctest --test-dir build --output-on-failure\n"
            << "  LOOM_PLUGIN_PATH=$PWD/build/lib/loom/plugins " << (prefix / "bin" / "loom").string()
            << " run graphs/exposure.json --out out\n";
  if (!installed)
    std::cout << "\nnote: " << prefix.string() << " is a Loom build tree, not an install: run "
              << "`cmake --install " << prefix.string() << " --prefix DIR` and use DIR as "
              << "CMAKE_PREFIX_PATH and DIR/bin/loom instead\n";
  return kOk;
}

}  // namespace loom::runner
