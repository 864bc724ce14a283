#include "loom/call_node.hpp"

#include "loom/error.hpp"
#include "loom/input_declaration.hpp"

namespace loom {
namespace {

// The inputs a call gives, and the defaults of the others; no progress, no
// cancellation, a fresh scratch and sequence state each time. A fetched
// value is kept for the call's length: Inputs::get hands out references.
class CallHost final : public NodeHost {
 public:
  CallHost(const NodeSpec& spec, const NodeCall& call) : spec_(spec), call_(call), fetched_(spec.inputs.size()) {}
  Value fetch_input(int index) override {
    Value& kept = fetched_[static_cast<std::size_t>(index)];
    if (kept) return kept;
    const InputSpec& in = spec_.inputs[static_cast<std::size_t>(index)];
    if (auto it = call_.values.find(in.name); it != call_.values.end())
      kept = it->second;
    else if (call_.literals.contains(in.name))
      kept = Value(in.type, in.type->from_json(call_.literals.at(in.name)));
    else
      kept = Value(in.type, in.type->from_json(in.default_value));
    return kept;
  }
  bool input_set(int index) const override {
    const InputSpec& in = spec_.inputs[static_cast<std::size_t>(index)];
    return call_.values.count(in.name) || call_.literals.contains(in.name) || in.has_default();
  }
  void report_progress(double, std::string_view) override {}
  void report(bool warning, std::string text) override {
    if (call_.report) call_.report(warning, text);
  }
  bool cancelled() const override { return false; }
  std::shared_ptr<void> scratch(std::uint64_t, const std::function<std::shared_ptr<void>()>& make) override {
    return make();
  }
  std::shared_ptr<void> sequence_state(const std::function<std::shared_ptr<void>()>& make) override {
    return make();
  }

 private:
  const NodeSpec& spec_;
  const NodeCall& call_;
  std::vector<Value> fetched_;
};

// Every given name is an input; every literal passes its declaration; every
// input without a default is given.
void check_call(const NodeSpec& spec, const NodeCall& call) {
  for (const auto& [name, value] : call.values)
    if (!spec.find_input(name)) throw Error(spec.name + " has no input \"" + name + "\"");
  for (const auto& [name, literal] : call.literals.items()) {
    const InputSpec* in = spec.find_input(name);
    if (!in) throw Error(spec.name + " has no input \"" + name + "\"");
    try {
      check_literal(*in, literal);
    } catch (const Error& e) {
      throw Error(spec.name + "'s input \"" + name + "\": " + e.what());
    }
  }
  for (const InputSpec& in : spec.inputs)
    if (in.required() && !call.values.count(in.name) && !call.literals.contains(in.name))
      throw Error(spec.name + "'s input \"" + in.name + "\" is required");
}

}  // namespace

std::vector<Value> call_node(const NodeType& type, const NodeCall& call) {
  check_call(type.spec, call);
  CallHost host(type.spec, call);
  Inputs in(type.spec, host);
  Outputs out(type.spec);
  Context ctx(host, call.id, 0, call.dir, call.dir);
  type.run(in, out, ctx);
  return std::move(out.values());
}

}  // namespace loom
