#include "held_value.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <map>
#include <mutex>
#include <vector>

#include <tbb/parallel_for.h>

#include "loom/builtin_types.hpp"
#include "loom/image.hpp"

namespace loom::python {

namespace {

struct Entry {
  Value value;
  int users = 0;
};
std::mutex g_mutex;
std::map<std::string, Entry> g_held;

void run_held_value(Inputs& in, Outputs& out, Context&) {
  const std::string& key = in.get<std::string>("key");
  std::lock_guard<std::mutex> lock(g_mutex);
  auto it = g_held.find(key);
  if (it == g_held.end()) throw Error("the in-memory value " + key + " is no longer held");
  out.set_value("value", it->second.value);
}

}  // namespace

NodeType held_value_type() {
  NodeType t;
  t.spec.name = "python.HeldValue";
  t.spec.describe("A value given from Python (a NumPy array, a loom.Mesh), found by its content hash.")
      .input<std::string>("key", "the value's content hash")
      .output<Any>("value", "the value");
  t.run = &run_held_value;
  return t;
}

namespace {

// The content hash of a value, as 16 hex digits: its serialized bytes, or its
// JSON for types that are not storable.
std::string content_key(const Value& value) {
  Hasher h;
  h.str(value.type()->name);
  if (value.is<Image>()) {  // the pixels in place: no serialized copy of a 100 MB image
    const Image& image = value.as<Image>();
    const cv::Mat& p = image.pixels;
    h.pod(p.rows).pod(p.cols).pod(p.channels()).pod(int(image.encoding)).pod(image.space.size()).str(image.space);
    // Bands of kBand rows hashed in parallel, their digests then in order:
    // the same key whatever the thread count.
    constexpr int kBand = 32;
    std::vector<std::uint64_t> bands(std::size_t((p.rows + kBand - 1) / kBand));
    tbb::parallel_for(std::size_t(0), bands.size(), [&](std::size_t b) {
      Hasher band;
      for (int y = int(b) * kBand; y < std::min(p.rows, int(b + 1) * kBand); ++y)
        band.bytes(p.ptr(y), p.elemSize() * std::size_t(p.cols));
      bands[b] = band.digest();
    });
    for (const std::uint64_t d : bands) h.pod(d);
  } else if (value.type()->storable()) {
    ByteWriter w;
    value.type()->write(value.data(), w);
    h.bytes(w.buffer().data(), w.buffer().size());
  } else if (value.type()->to_json) {
    h.str(value.type()->to_json(value.data()).dump());
  } else {
    h.pod(reinterpret_cast<std::uintptr_t>(value.data()));  // opaque: its identity
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h.digest()));
  return text;
}

}  // namespace

Held hold(const Value& value) { return Held{value, content_key(value)}; }

void HeldValues::link(Graph& graph, const std::string& node, const std::string& input, const Held& held) {
  const std::string& key = held.key;
  {
    std::lock_guard<std::mutex> lock(g_mutex);
    Entry& e = g_held[key];
    e.value = held.value;
    ++e.users;
  }
  keys_.push_back(key);
  const std::string id = "held_" + key;
  GraphNode& node_of_value = graph.nodes[id];
  node_of_value.id = id;
  node_of_value.type = "python.HeldValue";
  node_of_value.inputs["key"].literal = key;
  graph.nodes.at(node).inputs[input] = InputBinding{Link{id, "value"}, json()};
}

HeldValues::~HeldValues() {
  std::lock_guard<std::mutex> lock(g_mutex);
  for (const std::string& key : keys_) {
    auto it = g_held.find(key);
    if (it != g_held.end() && --it->second.users == 0) g_held.erase(it);
  }
}

}  // namespace loom::python
