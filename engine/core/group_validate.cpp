// Group interfaces against the registry: each declaration is an InputSpec a
// C++ node could declare, each value given to an instance passes the same
// literal check as a node input's, and each inner input an interface input
// feeds must take its type. Issues point into the file that wrote them.
#include <set>

#include "graph_groups.hpp"
#include "input_binding.hpp"
#include "json_text.hpp"

namespace loom::detail {

namespace {

class InterfaceCheck {
 public:
  InterfaceCheck(const Graph& g, const Registry& r, Issues& issues) : g_(g), registry_(r), issues_(issues) {}

  // The interface of `inst` (null: a group file's own) and what it is given.
  void check(const GroupInterface& in, const GroupInstance* inst) {
    for (const auto& [name, input] : in.inputs) {
      std::optional<InputSpec> spec;
      try {
        spec = interface_input_spec(name, input.declaration);
      } catch (const Error& e) {
        once(input.place, input.place.pointer, "interface input \"" + name + "\": " + e.what());
        continue;
      }
      for (const Link& t : input.to) check_target(input, *spec, t);
      if (!inst) continue;
      auto given = inst->given.find(name);
      if (given != inst->given.end()) check_given(*inst, *spec, given->second);
    }
  }

  void check_type_name(const GroupInstance& inst) {
    if (const NodeType* t = registry_.find(inst.type))
      issues_.push_back({inst.place.pointer + "/type", "\"" + inst.type + "\" names both a group and a node type (of plugin " +
                                                           t->spec.plugin + "): rename the group",
                         inst.place.file});
  }

 private:
  const Graph& g_;
  const Registry& registry_;
  Issues& issues_;
  std::set<std::string> reported_;  // a group used by many instances is reported once

  void once(const SourcePlace& place, const std::string& pointer, std::string message) {
    if (reported_.insert(place.file + "\n" + pointer + "\n" + message).second)
      issues_.push_back({pointer, std::move(message), place.file});
  }

  // The type an inner input (or a nested instance's interface input) takes.
  const TypeInfo* target_type(const Link& t, std::string& problem) {
    if (auto inst = g_.instances.find(t.node); inst != g_.instances.end()) {
      auto in = inst->second.interface.inputs.find(t.output);
      if (in == inst->second.interface.inputs.end()) return nullptr;
      try {
        return interface_input_spec(t.output, in->second.declaration).type;
      } catch (const Error&) {
        return nullptr;  // reported at that declaration
      }
    }
    auto n = g_.nodes.find(t.node);
    const NodeType* type = n == g_.nodes.end() ? nullptr : node_type_of(n->second, registry_);
    if (!type) return nullptr;  // reported at the node
    const InputSpec* spec = type->spec.find_input(t.output);
    if (!spec) {
      std::string known;
      for (const auto& s : type->spec.inputs) known += (known.empty() ? "" : ", ") + s.name;
      problem = "node \"" + t.node + "\" (" + type->spec.name + ") has no input \"" + t.output + "\" (its inputs: " +
                known + ")";
    }
    return spec ? spec->type : nullptr;
  }

  void check_target(const GroupInput& input, const InputSpec& spec, const Link& t) {
    std::string problem;
    const TypeInfo* inner = target_type(t, problem);
    if (!problem.empty()) once(input.place, input.place.pointer + "/to", "interface input \"" + spec.name + "\": " + problem);
    if (inner && !link_compatible(*spec.type, *inner))
      once(input.place, input.place.pointer + "/type",
           "interface input \"" + spec.name + "\" is " + spec.type->name + " but it feeds " + t.node + "." + t.output +
               ", which expects " + inner->name);
  }

  void check_given(const GroupInstance& inst, const InputSpec& spec, const InputBinding& b) {
    const std::string ip = inst.place.pointer + "/inputs/" + pointer_escape(spec.name);
    const std::string source = b.set_by.empty() ? inst.place.file : b.set_by;
    if (!b.link) {
      try {
        literal_value(spec, b.literal);
      } catch (const Error& e) {
        issues_.push_back({ip, e.what(), source});
      }
      return;
    }
    auto up = g_.nodes.find(b.link->node);
    const NodeType* ut = up == g_.nodes.end() ? nullptr : node_type_of(up->second, registry_);
    const int o = ut ? ut->spec.output_index(b.link->output) : -1;
    if (o < 0) return;  // reported at the inner inputs it feeds
    const TypeInfo* have = ut->spec.outputs[static_cast<std::size_t>(o)].type;
    if (!link_compatible(*have, *spec.type))
      issues_.push_back({ip + "/from", "type mismatch: " + b.link->node + "." + b.link->output + " is " + have->name +
                                           " but group input \"" + spec.name + "\" expects " + spec.type->name,
                         source});
  }
};

}  // namespace

void validate_groups(const Graph& g, const Registry& registry, Issues& issues) {
  InterfaceCheck check(g, registry, issues);
  for (const auto& [path, inst] : g.instances) {
    check.check_type_name(inst);
    check.check(inst.interface, &inst);
  }
  if (g.interface) check.check(*g.interface, nullptr);
}

}  // namespace loom::detail
