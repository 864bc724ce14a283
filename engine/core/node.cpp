#include "loom/node.hpp"

#include <cxxabi.h>

#include <algorithm>
#include <cstdlib>
#include <memory>


namespace loom {

namespace {

// "loom::warp::RbfKernel" for typeid(RbfKernel).name(), for messages.
std::string readable_type(const std::string& mangled) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> name(abi::__cxa_demangle(mangled.c_str(), nullptr, nullptr, &status),
                                              std::free);
  return status == 0 && name ? std::string(name.get()) : mangled;
}

}  // namespace

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
NodeSpec& NodeSpec::set_sequence_sink() {
  sink = sequence = true;
  return *this;
}
NodeSpec& NodeSpec::set_pixel_independent(SummarizeFunction summarize_outputs) {
  pixel_independent = true;
  summarize = summarize_outputs;
  return *this;
}
NodeSpec& NodeSpec::set_sample_passes() {
  pixel_independent = sample_passes = true;
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

NodeSpec& NodeSpec::add_enum_input(std::string input_name, std::string text, std::vector<std::string> names,
                                   std::vector<std::int64_t> values, std::int64_t default_value,
                                   const char* cpp_type) {
  const std::string where = "node " + name + ", enum input \"" + input_name + "\": ";
  if (names.empty()) throw Error(where + "no choices");
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t k = 0; k < i; ++k)
      if (names[k] == names[i]) throw Error(where + "the choice \"" + names[i] + "\" is named twice");
  const auto d = std::find(values.begin(), values.end(), default_value);
  if (d == values.end()) throw Error(where + "the default value is not one of the choices");
  add_input(std::move(input_name), std::move(text), &enum_type(), json(names[static_cast<std::size_t>(d - values.begin())]));
  InputSpec& in = last_input();
  in.choices = std::move(names);
  in.choice_values = std::move(values);
  in.enum_cpp_type = cpp_type;
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

std::int64_t Inputs::enum_value(std::string_view input_name, const char* cpp_type) {
  const InputSpec& spec = spec_.inputs[static_cast<std::size_t>(index(input_name))];
  auto bug = [&](const std::string& what) {
    return Error("input \"" + spec.name + "\" " + what + " (a bug in node " + spec_.name + ": get<" +
                 readable_type(cpp_type) + ">(\"" + spec.name + "\") does not match the input's declaration)");
  };
  if (spec.type != &enum_type() || spec.choices.empty()) throw bug("is " + spec.type->name + ", not an enum");
  if (spec.choice_values.empty())
    throw bug("is an enum declared with strings only: read it with get<std::string>, or declare it with its "
              "values, enum_input(name, E::value, {{E::value, \"name\"}, ...}, text)");
  if (spec.enum_cpp_type != cpp_type) throw bug("is declared with values of enum " + readable_type(spec.enum_cpp_type));
  const Value v = value(input_name);
  // The engine checked the value against the choices when it arrived; the
  // loop still refuses an unknown string rather than map it to some value.
  const std::string& choice = v.as<std::string>();
  for (std::size_t k = 0; k < spec.choices.size(); ++k)
    if (spec.choices[k] == choice) return spec.choice_values[k];
  throw Error("input \"" + spec.name + "\": \"" + choice + "\" is not one of its choices");
}

bool Inputs::has(std::string_view input_name) const { return host_.input_set(index(input_name)); }

const Value& Outputs::value(std::string_view output_name) const {
  int i = spec_.output_index(output_name);
  if (i < 0)
    throw Error("node type " + spec_.name + " has no output \"" + std::string(output_name) + "\"");
  return values_[static_cast<std::size_t>(i)];
}

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
