#include "cli/target_json.hpp"

#include "loom/graph_view.hpp"

namespace loom::runner {

json value_json(const Value& v) {
  if (v.type() && v.type()->to_json) return v.to_json();
  return {{"type", v.type() ? v.type()->name : "empty"}, {"summary", v.summary()}};
}

std::string target_json(const Graph& graph, const Registry& registry, const EvalResult& result) {
  json out = json::object();
  for (const auto& [name, values] : named_outputs_per_frame(GraphView(graph, registry), result)) {
    if (values.size() == 1) {
      out[name] = value_json(values[0]);
      continue;
    }
    json frames = json::array();  // kept at several frames: one entry per frame, in order
    for (const Value& v : values) frames.push_back(value_json(v));
    out[name] = std::move(frames);
  }
  return out.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace loom::runner
