#include "input_binding.hpp"
#include "output_confinement.hpp"

#include <cmath>
#include <sstream>

#include "loom/frame_pattern.hpp"
#include "loom/suggest.hpp"

namespace loom::detail {

namespace fs = std::filesystem;

namespace {

std::string range_text(const InputSpec& spec) {
  std::ostringstream s;
  if (spec.min && spec.max) s << "between " << *spec.min << " and " << *spec.max;
  else if (spec.min) s << "at least " << *spec.min;
  else s << "at most " << *spec.max;
  return s.str();
}

void check_number(const InputSpec& spec, double v, const std::string& shown) {
  const bool ok = std::isfinite(v) ? !((spec.min && v < *spec.min) || (spec.max && v > *spec.max))
                                   : (!spec.min && !spec.max && !std::isnan(v));
  if (!ok) throw Error("value " + shown + " is out of range: expected " + range_text(spec));
}

void check_json_numbers(const InputSpec& spec, const json& j, const json& whole) {
  if (j.is_number()) {
    check_number(spec, j.get<double>(), whole.dump(-1, ' ', false, json::error_handler_t::replace).substr(0, 80));
  } else if (j.is_array()) {
    for (const json& e : j) check_json_numbers(spec, e, whole);
  }
}

void check_choice(const InputSpec& spec, const std::string& s) {
  for (const auto& c : spec.choices)
    if (c == s) return;
  std::string list;
  for (const auto& c : spec.choices) list += (list.empty() ? "\"" : ", \"") + c + "\"";
  const std::vector<std::string> near = near_names(s, spec.choices);
  for (std::size_t i = 0; i < near.size(); ++i)
    list += (i == 0 ? "; did you mean \"" : i + 1 == near.size() ? " or \"" : ", \"") + near[i] + "\"";
  throw Error("\"" + s.substr(0, 80) + "\" is not one of the choices: " + list + (near.empty() ? "" : "?"));
}

void refuse_control_characters(const std::string& path) {
  if (path.empty()) throw Error("the path is empty");
  for (unsigned char c : path)
    if (c < 0x20 || c == 0x7f)
      throw Error("the path contains a NUL or control character (byte " + std::to_string(static_cast<int>(c)) +
                  ")");
}

std::string bind_path(const InputSpec& spec, const std::string& path, const BindingPlace& place) {
  if (spec.role == InputRole::input_file) return resolve_input_path(path, place.graph_dir);
  return resolve_output_path(expand_frame_pattern(path, place.frame), place.output_dir,
                             place.allow_outside_output);
}

}  // namespace

Value convert_literal(const InputSpec& spec, const json& literal) {
  if (!spec.type->literal())
    throw Error(spec.type->name + " values cannot be written in a graph file: link this input " +
                "to a node output, e.g. {\"from\": \"ID.OUTPUT\"}");
  try {
    return Value(spec.type, spec.type->from_json(literal));
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // a JSON library error in a conversion
    throw Error("expected " + spec.type->name + ", got " + describe_json(literal) + " (" + e.what() + ")");
  }
}

void check_declared(const InputSpec& spec, const Value& value) {
  if (!value || (!spec.min && !spec.max && spec.choices.empty())) return;
  const TypeInfo* type = value.type();
  if (!spec.choices.empty() && type->storage == enum_type().storage) return check_choice(spec, value.as<std::string>());
  if (!spec.min && !spec.max) return;
  if (type->storage == type_of<double>().storage) {
    const double v = value.as<double>();
    return check_number(spec, v, std::isfinite(v) ? json(v).dump() : std::to_string(v));
  }
  if (type->storage == type_of<int>().storage) {
    const int v = value.as<int>();
    return check_number(spec, v, std::to_string(v));
  }
  // Vectors and lists of numbers: per component, through their JSON form.
  if (type->literal()) {
    const json j = value.to_json();
    check_json_numbers(spec, j, j);
  }
}

Value literal_value(const InputSpec& spec, const json& literal) {
  Value v = convert_literal(spec, literal);
  check_declared(spec, v);
  return v;
}

Value bind_value(const InputSpec& spec, const Value& value, const BindingPlace& place) {
  try {
    // Validation checks link types; only an Any output (Switch's, a Python
    // node's) can bring another type, which the node would meet as
    // "value is Float, not Int" naming no input.
    if (value && !is_any(*spec.type) && value.type()->storage != spec.type->storage)
      throw Error("a " + value.type()->name + " value arrived (through an output of type Any), but the input is " +
                  spec.type->name);
    check_declared(spec, value);
    if (spec.role == InputRole::value || !value) return value;
    return Value::make<std::string>(bind_path(spec, value.as<std::string>(), place));
  } catch (const Error& e) {
    throw Error("input \"" + spec.name + "\": " + e.what());
  }
}

std::string resolve_output_path(const std::string& path, const fs::path& output_dir, bool allow_outside) {
  refuse_control_characters(path);
  fs::path p = path;
  if (p.is_absolute()) {
    if (!allow_outside)
      throw Error("output path \"" + path + "\" is absolute: output files go under the output folder (--out); "
                  "run with --allow-outside-out to write elsewhere");
    return p.lexically_normal().string();
  }
  const fs::path resolved = (output_dir / p).lexically_normal();
  const fs::path rel = resolved.lexically_relative(output_dir.lexically_normal());
  if (!allow_outside && (rel.empty() || *rel.begin() == ".."))
    throw Error("output path \"" + path + "\" leaves the output folder: \"..\" may not climb out of --out; "
                "run with --allow-outside-out to write elsewhere");
  if (!allow_outside) require_inside_real_output(resolved, output_dir, path);
  return resolved.string();
}

std::string resolve_input_path(const std::string& path, const fs::path& graph_dir) {
  refuse_control_characters(path);
  fs::path p = path;
  if (p.is_relative()) p = graph_dir / p;
  return p.lexically_normal().string();
}

}  // namespace loom::detail
