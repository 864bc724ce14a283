#include "loom/node.hpp"

#include <algorithm>

namespace loom {

NodeSpec& NodeSpec::describe(std::string text) {
  description = std::move(text);
  return *this;
}
NodeSpec& NodeSpec::set_version(int v) {
  version = v;
  return *this;
}
NodeSpec& NodeSpec::set_sink() {
  sink = true;
  return *this;
}
NodeSpec& NodeSpec::set_nondeterministic() {
  nondeterministic = true;
  return *this;
}

NodeSpec& NodeSpec::set_time_dependent() {
  time_dependent = true;
  return *this;
}
NodeSpec& NodeSpec::set_simulation(std::string state_input_name, std::string state_output_name) {
  state_input = std::move(state_input_name);
  state_output = std::move(state_output_name);
  time_dependent = true;
  return *this;
}

NodeSpec& NodeSpec::add_input(std::string input_name, std::string text, const TypeInfo* type,
                              json default_value) {
  InputSpec in;
  in.name = std::move(input_name);
  in.description = std::move(text);
  in.type = type;
  in.default_value = std::move(default_value);
  inputs.push_back(std::move(in));
  return *this;
}

NodeSpec& NodeSpec::enum_input(std::string input_name, std::string default_choice,
                               std::vector<std::string> choices, std::string text) {
  add_input(std::move(input_name), std::move(text), &enum_type(), json(default_choice));
  last_input().choices = std::move(choices);
  return *this;
}

InputSpec& NodeSpec::last_input() {
  if (inputs.empty()) throw Error("node " + name + ": a modifier came before any input");
  return inputs.back();
}

NodeSpec& NodeSpec::range(double lo, double hi) {
  last_input().min = lo;
  last_input().max = hi;
  return *this;
}
NodeSpec& NodeSpec::at_least(double lo) {
  last_input().min = lo;
  return *this;
}
NodeSpec& NodeSpec::optional() {
  last_input().optional = true;
  return *this;
}
NodeSpec& NodeSpec::lazy() {
  last_input().lazy = true;
  return *this;
}
NodeSpec& NodeSpec::input_file() {
  last_input().role = InputRole::input_file;
  return *this;
}
NodeSpec& NodeSpec::output_file() {
  last_input().role = InputRole::output_file;
  return *this;
}

const InputSpec* NodeSpec::find_input(std::string_view input_name) const {
  int i = input_index(input_name);
  return i < 0 ? nullptr : &inputs[static_cast<std::size_t>(i)];
}
int NodeSpec::input_index(std::string_view input_name) const {
  for (std::size_t i = 0; i < inputs.size(); ++i)
    if (inputs[i].name == input_name) return static_cast<int>(i);
  return -1;
}
int NodeSpec::output_index(std::string_view output_name) const {
  for (std::size_t i = 0; i < outputs.size(); ++i)
    if (outputs[i].name == output_name) return static_cast<int>(i);
  return -1;
}

int Inputs::index(std::string_view input_name) const {
  int i = spec_.input_index(input_name);
  if (i < 0)
    throw Error("node type " + spec_.name + " has no input \"" + std::string(input_name) +
                "\" (a bug in the node: it asked for an input it did not declare)");
  return i;
}

Value Inputs::value(std::string_view input_name) {
  int i = index(input_name);
  if (!host_.input_set(i))
    throw Error("input \"" + std::string(input_name) + "\" is not set");
  return host_.fetch_input(i);
}

bool Inputs::has(std::string_view input_name) const { return host_.input_set(index(input_name)); }

void Outputs::set_value(std::string_view output_name, Value value) {
  int i = spec_.output_index(output_name);
  if (i < 0)
    throw Error("node type " + spec_.name + " has no output \"" + std::string(output_name) + "\"");
  const TypeInfo* want = spec_.outputs[static_cast<std::size_t>(i)].type;
  if (!value || (!is_any(*want) && value.type()->storage != want->storage))
    throw Error("output \"" + std::string(output_name) + "\" is declared " + want->name +
                " but was set to " + (value.type() ? value.type()->name : "nothing"));
  values_[static_cast<std::size_t>(i)] = std::move(value);
}

void Context::progress(double done, double total, std::string_view label) {
  double f = total > 0 ? std::clamp(done / total, 0.0, 1.0) : 0.0;
  host_.report_progress(f, label);
}

}  // namespace loom
