#include "loom/input_declaration.hpp"

#include "input_binding.hpp"
#include "loom/builtin_types.hpp"
#include "loom/suggest.hpp"

namespace loom {

namespace {

// Types register at their first use (type_of<T>); a declaration may name one
// before any node has used it. The engine's own are registered here; the
// types of libloom_types (Image, Mesh...) are by the plugins that use them.
void register_builtin_types() {
  static const bool registered = [] {
    (void)type_of<bool>(), (void)type_of<int>(), (void)type_of<double>(), (void)type_of<std::string>();
    (void)type_of<Vec2i>(), (void)type_of<Vec2>(), (void)type_of<Vec3i>(), (void)type_of<Vec3>();
    (void)type_of<Color>(), (void)type_of<std::vector<int>>(), (void)type_of<std::vector<double>>();
    (void)type_of<std::vector<std::string>>(), (void)type_of<std::vector<Vec2>>();
    (void)type_of<std::vector<Vec3>>(), (void)type_of<json>(), (void)type_of<Any>(), (void)enum_type();
    return true;
  }();
  (void)registered;
}

[[noreturn]] void refuse(const char* key, const std::string& what) {
  throw Error(std::string("\"") + key + "\": " + what);
}

const TypeInfo* type_of_declaration(const json& d, DeclarationReading reading) {
  register_builtin_types();
  const json& type = d.contains("type") ? d["type"] : json();
  const TypeInfo* t = type.is_string() ? find_type(type.get<std::string>()) : nullptr;
  if (t || reading == DeclarationReading::lenient) return t ? t : &type_of<Any>();
  if (!type.is_string()) refuse("type", "expected the name of a type, got " + describe_json(type));
  try {
    return &declared_type(type.get<std::string>());
  } catch (const Error& e) {
    refuse("type", e.what());
  }
}

// Reads d[key] with `read` when it is there; a value `read` refuses is an
// error when strict and left at its default when lenient.
template <class Read>
void read_key(const json& d, const char* key, DeclarationReading reading, Read read) {
  if (!d.contains(key)) return;
  try {
    read(d[key]);
  } catch (const Error& e) {
    if (reading == DeclarationReading::strict) refuse(key, e.what());
  }
}

}  // namespace

const TypeInfo& declared_type(const std::string& name) {
  register_builtin_types();
  if (const TypeInfo* t = find_type(name)) return *t;
  const auto near = near_names(name, type_names(), 1);
  throw Error("unknown type \"" + name + "\"" + (near.empty() ? "" : "; did you mean \"" + near.front() + "\"?"));
}

InputSpec input_spec_from_json(const std::string& name, const json& d, DeclarationReading reading) {
  InputSpec s;
  s.name = name;
  s.type = type_of_declaration(d, reading);
  read_key(d, "description", reading, [&](const json& v) {
    if (!v.is_string()) throw Error("expected a string, got " + describe_json(v));
    s.description = v;
  });
  read_key(d, "optional", reading, [&](const json& v) {
    if (!v.is_boolean()) throw Error("expected true or false, got " + describe_json(v));
    s.optional = v;
  });
  for (const char* key : {"min", "max"})
    read_key(d, key, reading, [&](const json& v) {
      if (!v.is_number()) throw Error("expected a number, got " + describe_json(v));
      (std::string(key) == "min" ? s.min : s.max) = v.get<double>();
    });
  read_key(d, "choices", reading, [&](const json& v) {
    if (!v.is_array() || v.empty()) throw Error("expected a list of strings, got " + describe_json(v));
    for (const json& c : v)
      if (!c.is_string()) throw Error("expected strings, got " + describe_json(c));
    s.choices = v.get<std::vector<std::string>>();
  });
  if (reading == DeclarationReading::strict && s.type == &enum_type() && s.choices.empty())
    throw Error("an Enum input needs \"choices\"");
  read_key(d, "default", reading, [&](const json& v) {
    if (reading == DeclarationReading::strict) check_literal(s, v);
    s.default_value = v;
  });
  return s;
}

json input_spec_to_json(const InputSpec& s) {
  json d = {{"type", s.type->name}};
  if (s.has_default()) d["default"] = s.default_value;
  if (s.min) d["min"] = *s.min;
  if (s.max) d["max"] = *s.max;
  if (!s.choices.empty()) d["choices"] = s.choices;
  if (s.optional) d["optional"] = true;
  if (!s.description.empty()) d["description"] = s.description;
  return d;
}

void check_literal(const InputSpec& spec, const json& literal) { detail::literal_value(spec, literal); }

}  // namespace loom
