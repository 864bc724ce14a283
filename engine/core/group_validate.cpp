// Group interfaces against the registry: each declaration is an InputSpec a
// C++ node could declare, each value given to an instance passes the same
// literal check as a node input's, and each inner input an interface input
// feeds must take its type. Issues point into the file that wrote them.
#include <algorithm>
#include <set>

#include "graph_groups.hpp"
#include "group_validate.hpp"
#include "input_binding.hpp"
#include "json_text.hpp"
#include "loom/suggest.hpp"
#include "repeat.hpp"

namespace loom::detail {

namespace {

class InterfaceCheck {
 public:
  InterfaceCheck(const Graph& g, const Registry& r, const std::vector<std::string>& known, Issues& issues)
      : g_(g), registry_(r), known_(known), issues_(issues) {}

  // The interface of `inst` at `path` (null and "": a group file's own) and
  // what it is given.
  void check(const GroupInterface& in, const GroupInstance* inst, const std::string& path) {
    for (const auto& [name, input] : in.inputs) {
      std::string problem;
      const InputSpec* spec = input.spec(&problem);
      if (!spec) {
        once(input.place, input.place.pointer, "interface input \"" + name + "\": " + problem);
        continue;
      }
      for (std::size_t k = 0; k < input.to.size(); ++k) check_target(input, *spec, input.to[k], k, path);
      if (!inst) continue;
      auto given = inst->given.find(name);
      if (given != inst->given.end()) check_given(*inst, *spec, given->second);
    }
  }

  // Also a type of a plugin not loaded: the graph names the group only, so
  // that plugin is never loaded, and the group silently replaced its type.
  void check_type_name(const GroupInstance& inst) {
    const NodeType* t = registry_.find(inst.type);
    if (!t && std::find(known_.begin(), known_.end(), inst.type) == known_.end()) return;
    once(inst.place, inst.place.pointer + "/type",
         "\"" + inst.type + "\" names both a group and a node type" + (t ? " (of plugin " + t->spec.plugin + ")" : "") +
             ": rename the group");
  }

 private:
  const Graph& g_;
  const Registry& registry_;
  const std::vector<std::string>& known_;
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
      const InputSpec* spec = in == inst->second.interface.inputs.end() ? nullptr : in->second.spec();
      return spec ? spec->type : nullptr;  // invalid: reported at the declaration
    }
    auto n = g_.nodes.find(t.node);
    const NodeType* type = n == g_.nodes.end() ? nullptr : node_type_of(n->second, registry_);
    if (!type) return nullptr;  // reported at the node
    const InputSpec* spec = type->spec.find_input(t.output);
    if (!spec) {
      std::string known;
      std::vector<std::string> names;
      for (const auto& s : type->spec.inputs) {
        known += (known.empty() ? "" : ", ") + s.name;
        names.push_back(s.name);
      }
      const auto near = near_names(t.output, names, 1);
      problem = "has no input \"" + t.output + "\"" + (near.empty() ? "" : ": did you mean \"" + near[0] + "\"?") +
                " (" + type->spec.name + "'s inputs: " + known + ")";
    }
    return spec ? spec->type : nullptr;
  }

  // Reported once per definition, not per instance: the inner node is named
  // as the group writes it ("p", not "look.p").
  void check_target(const GroupInput& input, const InputSpec& spec, const Link& t, std::size_t k,
                    const std::string& path) {
    std::string problem;
    const TypeInfo* inner = target_type(t, problem);
    const std::string node = !path.empty() && t.node.rfind(path + ".", 0) == 0 ? t.node.substr(path.size() + 1) : t.node;
    if (!problem.empty())
      once(input.place, input.place.pointer + "/to/" + std::to_string(k),
           "interface input \"" + spec.name + "\" feeds " + link_text(node, t.output) + ", but node \"" + node + "\" " +
               problem);
    if (inner && !link_compatible(*spec.type, *inner))
      once(input.place, input.place.pointer + "/type",
           "interface input \"" + spec.name + "\" is " + spec.type->name + " but it feeds " + link_text(t) +
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
      issues_.push_back({ip + "/from",
                         "type mismatch: " + link_text(*b.link) + " is " + have->name + " but group input \"" +
                             spec.name + "\" expects " + spec.type->name,
                         source});
  }
};

}  // namespace

void validate_groups(const Graph& g, const Registry& registry, const std::vector<std::string>& known_types,
                     Issues& issues) {
  InterfaceCheck check(g, registry, known_types, issues);
  for (const auto& [path, inst] : g.instances) {
    check.check_type_name(inst);
    check.check(inst.interface, &inst, path);
  }
  if (g.interface) check.check(*g.interface, nullptr, "");
}

}  // namespace loom::detail
