#include "target_json.hpp"

namespace loom::runner {

namespace {

json value_json(const Value& v) {
  if (v.type() && v.type()->to_json) return v.to_json();
  return {{"type", v.type() ? v.type()->name : "empty"}, {"summary", v.summary()}};
}

}  // namespace

std::string target_json(const Graph& graph, const Registry& registry, const EvalResult& result) {
  json out = json::object();
  for (const auto& [name, values] : result.outputs) {
    if (name.find('.') != std::string::npos) {  // ID.OUTPUT: its value, or one per frame
      if (values.size() == 1) {
        out[name] = value_json(values[0]);
      } else {
        json frames = json::array();
        for (const auto& v : values) frames.push_back(value_json(v));
        out[name] = std::move(frames);
      }
      continue;
    }
    const NodeType* type = registry.find(graph.nodes.at(name).type);
    for (std::size_t i = 0; i < values.size(); ++i) {
      const std::string output = type && i < type->spec.outputs.size() ? type->spec.outputs[i].name
                                                                       : std::to_string(i);
      out[name + "." + output] = value_json(values[i]);
    }
  }
  return out.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace loom::runner
