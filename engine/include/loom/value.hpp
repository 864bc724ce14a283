// Plugin author API. Values: immutable, shared, typed by a name registered in the engine.
//
// A Value is a std::shared_ptr<const void> plus the TypeInfo of its type, so
// fan-out and caching copy a pointer, never pixels. Types are identified by
// name ("Image", "Mesh", "Float"), never by typeid, because typeid is not
// reliable across dlopen boundaries; the one table of names lives in libloom.
//
// To make a C++ type a Loom type, specialize TypeTraits:
//
//   template <> struct loom::TypeTraits<MyThing> {
//     static constexpr const char* name = "MyThing";
//     static constexpr const char* description = "what it is";
//     // optional: literals in graph files
//     static MyThing from_json(const loom::json& j);   // throw loom::Error
//     static loom::json to_json(const MyThing& v);
//     // optional: one line for logs and `--target` ("Image 512x512x3 linear")
//     static std::string summary(const MyThing& v);
//     // optional: storage in the persistent cache (see loom/serialize.hpp);
//     // bump version when the format changes
//     static constexpr int version = 1;
//     static void write(const MyThing& v, loom::ByteWriter& w);
//     static MyThing read(loom::ByteReader& r);
//     // optional: memory held, for the simulation-state budget (without it a
//     // storable value is measured by writing it)
//     static std::size_t bytes(const MyThing& v);
//     // optional: throws loom::Error when a value is unusable (NaN or
//     // infinite numbers, indices out of range). The engine calls it on every
//     // output of every node, so no NaN travels downstream: keep it one scan.
//     static void check(const MyThing& v);
//   };
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include <nlohmann/json.hpp>

#include "loom/error.hpp"
#include "loom/export.hpp"
#include "loom/serialize.hpp"

namespace loom {

using json = nlohmann::json;

struct TypeInfo {
  std::string name;
  std::string description;
  // The name of the type whose C++ object is stored: "String" for both String
  // and Enum. Value::as<T>() compares it with TypeTraits<T>::name.
  std::string storage;
  // Literal conversion from a graph file; empty for link-only types (Image).
  // Throws loom::Error saying what was expected.
  std::function<std::shared_ptr<const void>(const json&)> from_json;
  std::function<json(const void*)> to_json;  // empty for opaque types
  std::function<std::string(const void*)> summary;
  // Storage in the persistent cache; both empty for types that are never stored.
  int serial_version = 0;
  std::function<void(const void*, ByteWriter&)> write;
  std::function<std::shared_ptr<const void>(ByteReader&)> read;
  std::function<std::size_t(const void*)> bytes;  // optional: memory held
  std::function<void(const void*)> check;         // optional: throws on NaN, bad indices

  bool literal() const { return static_cast<bool>(from_json); }
  bool storable() const { return static_cast<bool>(write) && static_cast<bool>(read); }
};

// Registers a type by name, or returns the one already registered under that
// name (the first registration wins; names are the identity of types).
LOOM_API const TypeInfo& register_type(TypeInfo info);
// nullptr when no type of that name is registered.
LOOM_API const TypeInfo* find_type(std::string_view name);
// Registers an alias type (e.g. Enum stored as String) sharing the storage.
LOOM_API const TypeInfo& register_alias(std::string name, std::string description,
                                        const TypeInfo& storage);

template <class T>
struct TypeTraits;  // specialize per type; see the header comment

namespace detail {
template <class Tr, class = void>
struct has_from_json : std::false_type {};
template <class Tr>
struct has_from_json<Tr, std::void_t<decltype(Tr::from_json(std::declval<const json&>()))>>
    : std::true_type {};
template <class Tr, class T, class = void>
struct has_summary : std::false_type {};
template <class Tr, class T>
struct has_summary<Tr, T, std::void_t<decltype(Tr::summary(std::declval<const T&>()))>>
    : std::true_type {};
template <class Tr, class T, class = void>
struct has_serialization : std::false_type {};
template <class Tr, class T>
struct has_serialization<
    Tr, T,
    std::void_t<decltype(Tr::write(std::declval<const T&>(), std::declval<ByteWriter&>())),
                decltype(Tr::read(std::declval<ByteReader&>()))>> : std::true_type {};
template <class Tr, class = void>
struct has_serial_version : std::false_type {};
template <class Tr>
struct has_serial_version<Tr, std::void_t<decltype(Tr::version)>> : std::true_type {};
template <class Tr, class T, class = void>
struct has_bytes : std::false_type {};
template <class Tr, class T>
struct has_bytes<Tr, T, std::void_t<decltype(Tr::bytes(std::declval<const T&>()))>> : std::true_type {};
template <class Tr, class T, class = void>
struct has_check : std::false_type {};
template <class Tr, class T>
struct has_check<Tr, T, std::void_t<decltype(Tr::check(std::declval<const T&>()))>> : std::true_type {};
template <class Tr, class = void>
struct has_description : std::false_type {};
template <class Tr>
struct has_description<Tr, std::void_t<decltype(Tr::description)>> : std::true_type {};

template <class T>
TypeInfo make_type_info() {
  using Tr = TypeTraits<T>;
  TypeInfo info;
  info.name = Tr::name;
  info.storage = Tr::name;
  if constexpr (has_description<Tr>::value) info.description = Tr::description;
  if constexpr (has_from_json<Tr>::value) {
    info.from_json = [](const json& j) -> std::shared_ptr<const void> {
      return std::make_shared<const T>(Tr::from_json(j));
    };
    info.to_json = [](const void* p) { return Tr::to_json(*static_cast<const T*>(p)); };
  }
  if constexpr (has_summary<Tr, T>::value)
    info.summary = [](const void* p) { return Tr::summary(*static_cast<const T*>(p)); };
  else
    info.summary = [](const void*) { return std::string(Tr::name); };
  if constexpr (has_serialization<Tr, T>::value) {
    info.serial_version = 1;
    if constexpr (has_serial_version<Tr>::value) info.serial_version = Tr::version;
    info.write = [](const void* p, ByteWriter& w) { Tr::write(*static_cast<const T*>(p), w); };
    info.read = [](ByteReader& r) -> std::shared_ptr<const void> {
      return std::make_shared<const T>(Tr::read(r));
    };
  }
  if constexpr (has_bytes<Tr, T>::value)
    info.bytes = [](const void* p) { return Tr::bytes(*static_cast<const T*>(p)); };
  if constexpr (has_check<Tr, T>::value)
    info.check = [](const void* p) { Tr::check(*static_cast<const T*>(p)); };
  return info;
}
}  // namespace detail

// The TypeInfo of T, registered on first use from any library.
template <class T>
const TypeInfo& type_of() {
  static const TypeInfo& info = register_type(detail::make_type_info<T>());
  return info;
}

class Value {
 public:
  Value() = default;
  Value(const TypeInfo* type, std::shared_ptr<const void> data)
      : type_(type), data_(std::move(data)) {}

  template <class T>
  static Value make(T v) {
    return Value(&type_of<T>(), std::make_shared<const T>(std::move(v)));
  }
  template <class T>
  static Value share(std::shared_ptr<const T> p) {
    return Value(&type_of<T>(), std::move(p));
  }

  const TypeInfo* type() const { return type_; }
  const void* data() const { return data_.get(); }  // for TypeInfo's functions
  explicit operator bool() const { return static_cast<bool>(data_); }

  template <class T>
  bool is() const {
    return type_ && type_->storage == TypeTraits<T>::name;
  }
  template <class T>
  const T& as() const {
    if (!is<T>())
      throw Error(std::string("value is ") + (type_ ? type_->name : "empty") + ", not " +
                  TypeTraits<T>::name);
    return *static_cast<const T*>(data_.get());
  }
  template <class T>
  std::shared_ptr<const T> shared() const {
    as<T>();
    return std::static_pointer_cast<const T>(data_);
  }

  json to_json() const { return type_ && type_->to_json ? type_->to_json(data_.get()) : json(); }
  std::string summary() const { return type_ ? type_->summary(data_.get()) : "empty"; }
  // Throws loom::Error if the value is unusable (see TypeTraits::check).
  void check() const {
    if (type_ && type_->check && data_) type_->check(data_.get());
  }

 private:
  const TypeInfo* type_ = nullptr;
  std::shared_ptr<const void> data_;
};

}  // namespace loom
