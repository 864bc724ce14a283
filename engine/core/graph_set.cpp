// --set ID.INPUT=VALUE: an input's value given on the command line.
#include "graph_groups.hpp"
#include "graph_time.hpp"
#include "json_text.hpp"
#include "loom/graph.hpp"

namespace loom {

namespace {

// The value text as JSON; plain words are a string, but a value that looks
// like JSON and fails (deep nesting, 1e400) is an error, not silently a string.
json set_value(const std::string& assignment, const std::string& pointer, const std::string& text) {
  json value;
  const auto problem = detail::parse_json_text(text, value);
  if (!problem) return value;
  const auto first = text.find_first_not_of(" \t");
  const bool looks_json =
      first != std::string::npos && std::string("[{\"-0123456789").find(text[first]) != std::string::npos;
  if (looks_json) throw GraphError("--set " + detail::cut(assignment, 80), {{pointer, *problem}});
  return text;
}

// The value as an input binding: a literal, or a link {"from": "ID.OUTPUT"}
// (which may name a group instance's output).
InputBinding binding(const Graph& g, const std::string& source, const json& value, const std::string& text) {
  InputBinding b;
  b.set_by = source;
  if (value.is_object() && value.contains("from") && value["from"].is_string()) {
    auto link = parse_link(value["from"].get<std::string>());
    if (link) link = detail::follow_instance_outputs(g, *link);
    if (!link) throw GraphError(source, {{"", "expected {\"from\": \"ID.OUTPUT\"}, got " + detail::cut(text, 80)}});
    b.link = std::move(*link);
  } else {
    b.literal = value;
  }
  return b;
}

// --set look.width=640: an instance's interface input, fed to the inner
// inputs it names (replacing what the file gave them).
void set_interface_input(Graph& g, const std::string& id, const std::string& input, const std::string& source,
                         const json& value, const std::string& text) {
  const GroupInstance& inst = g.instances.at(id);
  if (!inst.interface.inputs.count(input)) {
    std::string known;
    for (const auto& [name, unused] : inst.interface.inputs) known += (known.empty() ? "" : ", ") + name;
    throw GraphError(source, {{inst.place.pointer + "/inputs/" + detail::pointer_escape(input),
                               "group instance \"" + id + "\" (" + inst.type + ") has no input \"" + input +
                                   "\" (its inputs: " + (known.empty() ? "none" : known) + ")"}});
  }
  detail::feed_input(g, {id, input}, binding(g, source, value, text), true);
}

}  // namespace

void set_input(Graph& g, const std::string& assignment) {
  const std::string source = "--set " + detail::cut(assignment, 80);
  if (!detail::valid_utf8(assignment)) throw GraphError("--set", {{"", "the assignment is not valid UTF-8 text"}});
  const auto eq = assignment.find('=');
  const auto name = eq == std::string::npos ? std::nullopt : parse_link(std::string_view(assignment).substr(0, eq));
  if (!name) throw GraphError("--set", {{"", "expected ID.INPUT=VALUE, got \"" + detail::cut(assignment, 80) + "\""}});
  const std::string& id = name->node;
  const std::string& input = name->output;
  const std::string text = assignment.substr(eq + 1);
  const json value = set_value(assignment, detail::input_pointer(id, input), text);
  auto it = g.nodes.find(id);
  if (it == g.nodes.end() && id == "time") {
    json t = g.time ? detail::time_to_json(*g.time) : json::object();
    t[input] = value;
    try {
      g.time = detail::parse_time(t);
    } catch (const GraphError& e) {
      throw GraphError(source, e.issues());
    }
    return;
  }
  if (it == g.nodes.end() && g.instances.count(id)) return set_interface_input(g, id, input, source, value, text);
  if (it == g.nodes.end())
    throw GraphError(source, {{detail::node_pointer(id), "--set names unknown node \"" + detail::cut(id, 80) +
                                                             "\" in " + g.file.string()}});
  it->second.inputs[input] = binding(g, source, value, text);
}

}  // namespace loom
