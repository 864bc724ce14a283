// `loom new-plugin NAME [--dir DIR]`: writes a complete out-of-tree plugin
// (CMakeLists.txt, plugin.cpp, one Image node, its GoogleTest test, an example
// graph, a README with the three commands) from the templates installed in
// <prefix>/share/loom/templates/plugin.
#pragma once

#include <filesystem>
#include <string>

namespace loom::runner {

// Where the plugin templates are: <bin>/../share/loom/templates/plugin.
std::filesystem::path plugin_template_dir();

// The node type of the scaffold: CamelCase of the plugin name + "Exposure"
// ("my_fx" -> "MyFxExposure"), so two scaffolded plugins do not clash.
std::string scaffold_node_name(const std::string& plugin);

// Writes DIR/NAME from the templates; prints the files and the next commands.
// Returns the exit code (2 for a bad name or an existing non-empty folder).
int new_plugin(const std::string& name, const std::filesystem::path& dir);

}  // namespace loom::runner
