// Plugin author API. What a node author writes against: the declaration (NodeSpec) and the three
// objects a node's run function receives (Inputs, Outputs, Context).
//
//   struct Checkerboard {
//     static constexpr const char* name = "Checkerboard";
//     static void declare(loom::NodeSpec& s) {
//       s.describe("A checkerboard image, for demos that need no files.")
//        .input<loom::Vec2i>("size", {512, 512}, "width and height in pixels").range(1, 16384)
//        .input<int>("cells", 8, "squares along the shorter side").range(1, 4096)
//        .output<loom::Image>("image", "the checkerboard");
//     }
//     static void run(loom::Inputs& in, loom::Outputs& out, loom::Context& ctx);
//   };
//   LOOM_NODE(Checkerboard);   // in the node's own .cpp, see loom/plugin.hpp
//
// The declaration is data: the runner prints it, the editor draws widgets from
// it and docs/nodes.md is generated from it. A node declares everything its
// result depends on; the engine, not the node, decides what to run and reuse.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

#include "loom/builtin_types.hpp"
#include "loom/hash.hpp"
#include "loom/value.hpp"

namespace loom {

enum class InputRole {
  value,        // an ordinary parameter or link
  input_file,   // a path read by the node: relative to the graph file's folder;
                // its size and mtime enter the computation hash
  output_file,  // a path written by the node: relative to the output folder
};

struct InputSpec {
  std::string name;
  std::string description;
  const TypeInfo* type = nullptr;
  json default_value;          // null: required (unless optional)
  bool optional = false;       // may stay unset: Inputs::has() is false
  bool lazy = false;           // fetched only when the node asks for it
  std::optional<double> min, max;  // per component, for numeric types
  std::vector<std::string> choices;  // for Enum: the strings graph files use
  // For an enum declared with its C++ values (enum_input<E>): choice_values[i]
  // is the value of choices[i] and enum_cpp_type identifies E, so that
  // Inputs::get<E> maps the string once, in the engine. Empty for an enum
  // declared with strings only.
  std::vector<std::int64_t> choice_values;
  std::string enum_cpp_type;
  InputRole role = InputRole::value;

  bool has_default() const { return !default_value.is_null(); }
  // The one rule for "must be linked or given in the graph file": no default
  // and not optional. Validation, the planner, `loom nodes` and the editor ask
  // this, never the fields themselves.
  bool required() const { return !has_default() && !optional; }
};

struct OutputSpec {
  std::string name;
  std::string description;
  const TypeInfo* type = nullptr;
};

// The frame a node is evaluated at. A graph without a "time" field is one
// evaluation at frame 1. Time is in seconds.
struct FrameTime {
  int frame = 1;     // the frame being evaluated
  int start = 1;     // the graph's first frame: simulations begin here
  double fps = 24;
  // For a simulation node (NodeSpec::set_simulation): the seconds to advance
  // in this evaluation. 0 at the start frame, where the node receives its
  // initial state and advances it by nothing (as in Blender's simulation
  // zones), 1/fps at every later frame. 0 for every other node.
  double step = 0;
  // The frames the current evaluation walks, in order (first == last == frame
  // for a single frame). A sink that gathers a sequence (SaveVideo) finishes
  // its file at `last`.
  int first = 1, last = 1;

  double seconds() const { return (frame - start) / fps; }  // since the start frame
};

// An enum input's choices with their C++ values, each named once: the name is
// what graph files, `loom nodes` and the editor show, the value what the node
// reads with in.get<E>(name).
//   const loom::EnumChoices<Method> methods = {{Method::idw, "idw"}, {Method::rbf, "rbf"}};
template <class E>
using EnumChoices = std::vector<std::pair<E, std::string>>;

// The pixels that a node declared set_pixel_independent() computes in one
// evaluation. The image is cut into tiles of tile x tile pixels, numbered row
// by row from the top left (the last column and row of tiles may be cut
// short), and the evaluation computes the tiles t with t % parts == part:
// interleaved tiles, OSPRay's static balancing, so every part gets a share of
// every region of the image. parts == 1 (the default): every pixel. The
// engine splits one image over processes (MPI ranks) this way and gathers the
// parts; a node only skips the pixels outside its part.
//
// A node declared set_sample_passes() (a path tracer: each pixel a mean of
// samples) may be split by samples instead (`by_samples`): it computes every
// pixel, taking the samples s with s % parts == part, and sums its per-pixel
// sums over the parts with Context::sum_over_parts after each pass, so that
// every part ends with the whole image (and adaptive sampling decides from
// every sample, as one process does).
//
// Split by samples and dealt as parts ask (`slots` > 0: loom run --mpi-deal
// dynamic), every pass is cut into `slots` shares: sample s of pixel p
// belongs to slot (s + spread(p)) % slots. A part takes the slots of a pass
// one at a time with Context::take_slot() until none is left, tracing each
// slot's samples, then sums (Context::sum_over_parts). spread() scatters the
// pixels over the slots, so that every slot is about 1/slots of the pass's
// work, for a pass of one sample a pixel as for one of many, and a faster
// part simply takes more slots.
struct PixelRegion {
  int tile = 32;
  int part = 0, parts = 1;
  bool by_samples = false;
  int slots = 0;  // dealt as parts ask: the slots in a pass

  bool whole() const { return parts <= 1; }
  bool dealt() const { return by_samples && slots > 0; }
  int tile_of(int x, int y, int width) const { return (y / tile) * ((width + tile - 1) / tile) + x / tile; }
  bool contains(int x, int y, int width) const {
    return whole() || by_samples || tile_of(x, y, width) % parts == part;
  }
  // Split by samples and not dealt: sample s of every pixel goes to part s % parts.
  bool takes_sample(std::int64_t sample) const { return whole() || !by_samples || sample % parts == part; }
  static std::uint64_t spread(std::size_t pixel) {
    return (std::uint64_t(pixel) * 0x9E3779B97F4A7C15ull) >> 40;  // Fibonacci hashing
  }
  int slot_of(std::size_t pixel, std::int64_t sample) const {
    return int((std::uint64_t(sample) + spread(pixel)) % std::uint64_t(slots));
  }
};

// What an intermediate value of an output says about itself
// (Context::publish_partial): how far the work is, and for a mean of samples
// the estimated relative error of the mean so far (negative: not known).
struct PartialInfo {
  double done = 0, total = 0;  // e.g. samples per pixel so far, and asked for
  std::string_view unit;       // what done counts ("spp", "iterations")
  double relative_error = -1;
};

class Inputs;
class Outputs;
class Context;
using RunFunction = void (*)(Inputs&, Outputs&, Context&);
// Recomputes outputs that summarize a whole image (a mean) once the engine has
// gathered the parts of a pixel-independent node's images (set_pixel_independent).
using SummarizeFunction = void (*)(Outputs&);

class LOOM_API NodeSpec {
 public:
  std::string name;
  std::string description;
  std::string plugin;  // set by the registry
  // The content identity of the plugin's library (its GNU build ID),
  // set by the plugin loader: it enters the persistent cache's keys, so a
  // rebuilt plugin never serves results of its previous build.
  std::uint64_t build = 0;
  int version = 1;     // bump when results change: it enters the cache hash
  bool sink = false;   // has side effects (writes files); always runs, never cached
  bool sequence = false;  // a sink that gathers every frame of a run into one file (set_sequence_sink)
  bool nondeterministic = false;  // never cached, nor is anything downstream
  bool time_dependent = false;    // reads ctx.time(): evaluated once per frame
  // Every Image output's pixel depends on nothing but the inputs and its own
  // position (set_pixel_independent): the engine may split the image.
  bool pixel_independent = false;
  SummarizeFunction summarize = nullptr;
  bool sample_passes = false;  // set_sample_passes
  // A simulation step (set_simulation): the names of its state input and output.
  std::string state_input, state_output;
  std::vector<InputSpec> inputs;
  std::vector<OutputSpec> outputs;
  // The file that defines the type when it is not a plugin's library (a
  // Python node's module): --watch follows it. Empty for C++ node types.
  std::string source_file;

  NodeSpec& describe(std::string text);
  NodeSpec& set_version(int v);
  NodeSpec& set_sink();
  // A sink that gathers the frames of one run, in order, into one file
  // (SaveVideo, with Context::sequence_state): a run split into chunks of
  // frames (loom submit, MPI) runs it once, after every frame, not per chunk.
  NodeSpec& set_sequence_sink();
  NodeSpec& set_nondeterministic();
  // Each pixel of every Image output is computed from the inputs and its own
  // position alone, so the engine may compute the image in parts
  // (Context::region(), e.g. over MPI ranks) and gather them: the node
  // computes only the pixels of its region (the others are overwritten). The
  // gathered image must equal the whole one bit for bit, so a pixel's random
  // numbers must come from (seed, pixel, sample), never from a shared stream.
  // Outputs of other types are taken from the first part, unless `summarize`
  // recomputes them from the gathered images (a mean over the pixels).
  NodeSpec& set_pixel_independent(SummarizeFunction summarize = nullptr);
  // A pixel-independent node whose pixels are means of numbered samples (a
  // path tracer) that takes its samples by PixelRegion (takes_sample, or the
  // slots of Context::take_slot) and calls Context::sum_over_parts after
  // each pass of samples: the engine may split
  // it by samples instead of tiles (loom run --mpi-split samples).
  NodeSpec& set_sample_passes();
  // The node reads ctx.time(). Nodes that do not are evaluated once and shared
  // by every frame; what depends on a time-dependent node is evaluated per
  // frame through its hash.
  NodeSpec& set_time_dependent();
  // A simulation step mapping the state at frame f-1 to the state at frame f
  // (Houdini's Solver SOP, Blender's simulation zone). At the graph's start
  // frame `state_input` takes what the graph links or gives (the initial
  // state) and ctx.time().step is 0; at every later frame f the engine feeds
  // `state_input` with this node's own `state_output` of frame f-1 and step is
  // 1/fps. Frames are computed in order and cached per frame. Both must be
  // declared, with the same type. Implies time_dependent.
  NodeSpec& set_simulation(std::string state_input_name, std::string state_output_name);
  bool simulation() const { return !state_output.empty(); }

  // A required input: it must be linked or given in the graph file.
  template <class T>
  NodeSpec& input(std::string input_name, std::string text) {
    return add_input(input_name, text, &type_of<T>(), json());
  }
  // An input with a default value.
  template <class T>
  NodeSpec& input(std::string input_name, T default_value, std::string text) {
    return add_input(input_name, text, &type_of<T>(), TypeTraits<T>::to_json(default_value));
  }
  // One of a set of strings, read as a C++ enum value by in.get<E>(name):
  //   s.enum_input("method", Method::rbf, {{Method::idw, "idw"}, {Method::rbf, "rbf"}}, "text")
  // The choices may be a subset of E's values; the default must be one of them.
  template <class E, class = std::enable_if_t<std::is_enum_v<E>>>
  NodeSpec& enum_input(std::string input_name, E default_value, const EnumChoices<E>& choices,
                       std::string text) {
    std::vector<std::string> names;
    std::vector<std::int64_t> values;
    for (const auto& [value, choice_name] : choices) {
      values.push_back(static_cast<std::int64_t>(value));
      names.push_back(choice_name);
    }
    return add_enum_input(std::move(input_name), std::move(text), std::move(names), std::move(values),
                          static_cast<std::int64_t>(default_value), typeid(E).name());
  }
  // One of a set of strings, read with in.get<std::string>(name).
  NodeSpec& enum_input(std::string input_name, std::string default_choice,
                       std::vector<std::string> choices, std::string text);
  template <class T>
  NodeSpec& output(std::string output_name, std::string text) {
    outputs.push_back({std::move(output_name), std::move(text), &type_of<T>()});
    return *this;
  }

  // Modifiers of the input declared last.
  NodeSpec& range(double min, double max);
  NodeSpec& at_least(double min);
  NodeSpec& optional();
  NodeSpec& lazy();
  NodeSpec& input_file();
  NodeSpec& output_file();

  const InputSpec* find_input(std::string_view input_name) const;
  int input_index(std::string_view input_name) const;   // -1 if absent
  int output_index(std::string_view output_name) const;  // -1 if absent

 private:
  NodeSpec& add_input(std::string input_name, std::string text, const TypeInfo* type,
                      json default_value);
  NodeSpec& add_enum_input(std::string input_name, std::string text, std::vector<std::string> names,
                           std::vector<std::int64_t> values, std::int64_t default_value,
                           const char* cpp_type);
  InputSpec& last_input();
};

struct NodeType {
  NodeSpec spec;
  RunFunction run = nullptr;
};

// The engine's side of Inputs and Context; node authors never see it.
class NodeHost {
 public:
  virtual ~NodeHost() = default;
  virtual Value fetch_input(int index) = 0;  // evaluates a lazy input on demand
  virtual bool input_set(int index) const = 0;
  virtual void report_progress(double fraction, std::string_view label) = 0;
  virtual void report(bool warning, std::string text) = 0;
  virtual bool cancelled() const = 0;
  virtual std::shared_ptr<void> scratch(std::uint64_t key,
                                        const std::function<std::shared_ptr<void>()>& make) = 0;
  virtual std::shared_ptr<void> sequence_state(const std::function<std::shared_ptr<void>()>& make) = 0;
  virtual void depends_on_file(const std::filesystem::path& path) { (void)path; }
  virtual PixelRegion pixel_region() const { return {}; }
  virtual void sum_over_parts(double* values, std::size_t count, double work) {
    (void)values;
    (void)count;
    (void)work;
  }
  virtual int take_slot() { return -1; }
  virtual bool partial_wanted() const { return false; }
  virtual void publish_partial(std::string_view output, Value value, const PartialInfo& info) {
    (void)output;
    (void)value;
    (void)info;
  }
};

class LOOM_API Inputs {
 public:
  Inputs(const NodeSpec& spec, NodeHost& host) : spec_(spec), host_(host) {}

  // The value of an input; a lazy input is computed on this first request.
  // A const T&, except for an enum input declared with enum_input<E>: get<E>
  // returns the E value of its choice (get<std::string> still returns the
  // choice's name). get<E> of an input that is not an enum of E throws.
  template <class T>
  decltype(auto) get(std::string_view input_name) {
    if constexpr (std::is_enum_v<T>)
      return static_cast<T>(enum_value(input_name, typeid(T).name()));
    else
      return value(input_name).as<T>();
  }
  // The shared pointer, to pass a value through without copying it.
  template <class T>
  std::shared_ptr<const T> share(std::string_view input_name) {
    return value(input_name).shared<T>();
  }
  Value value(std::string_view input_name);
  // False for an optional input left unset.
  bool has(std::string_view input_name) const;

 private:
  int index(std::string_view input_name) const;
  std::int64_t enum_value(std::string_view input_name, const char* cpp_type);
  const NodeSpec& spec_;
  NodeHost& host_;
};

class LOOM_API Outputs {
 public:
  explicit Outputs(const NodeSpec& spec) : spec_(spec), values_(spec.outputs.size()) {}

  template <class T>
  void set(std::string_view output_name, T value) {
    set_value(output_name, Value::make<T>(std::move(value)));
  }
  template <class T>
  void share(std::string_view output_name, std::shared_ptr<const T> value) {
    set_value(output_name, Value::share<T>(std::move(value)));
  }
  void set_value(std::string_view output_name, Value value);
  // An output set already (empty until set), e.g. by a SummarizeFunction.
  const Value& value(std::string_view output_name) const;

  std::vector<Value>& values() { return values_; }

 private:
  const NodeSpec& spec_;
  std::vector<Value> values_;
};

// Threads: a node body runs on one engine thread and may use
// tbb::parallel_for inside. From worker threads (inside parallel_for bodies)
// these calls are safe: progress(), cancelled(), check_cancelled() (it
// throws: catch nothing, TBB carries it out of the loop), warn(), log(),
// seed(), time(), node_id(), graph_dir(), output_dir(), and Inputs::get of
// inputs already fetched on the calling thread. Not safe: rng() (one
// generator; draw on the calling thread or seed per item from seed()),
// scratch(), Outputs::set, and the first get of a lazy input. Prefer reporting
// progress from the calling thread between chunks of rows (plugins/example);
// progress from workers is serialized, throttled and kept monotone per label.
class LOOM_API Context {
 public:
  // The strings and paths are the engine's and outlive the run.
  Context(NodeHost& host, const std::string& node_id, std::uint64_t seed,
          const std::filesystem::path& graph_dir, const std::filesystem::path& output_dir,
          FrameTime time = {})
      : host_(host), node_id_(node_id), seed_(seed), graph_dir_(graph_dir), output_dir_(output_dir),
        time_(time) {}

  const std::string& node_id() const { return node_id_; }

  // The frame being evaluated. Only nodes declared time-dependent (or
  // simulations) may read it to compute their outputs: the engine shares other
  // nodes' results across frames. Sinks run at every frame and may read it too.
  const FrameTime& time() const { return time_; }

  // Progress of long work: done out of total steps, with an optional label.
  // Cheap to call often; the engine throttles what it shows.
  void progress(double done, double total, std::string_view label = {});

  // Cooperative cancellation: call in loops that run for more than ~10 ms.
  bool cancelled() const { return host_.cancelled(); }
  void check_cancelled() const {
    if (host_.cancelled()) throw Cancelled();
  }

  // Seeded from the graph seed and the node id, never from thread order.
  std::uint64_t seed() const { return seed_; }
  std::mt19937_64& rng() {  // seeded on first use: most nodes draw nothing
    if (!rng_) rng_.emplace(seed_);
    return *rng_;
  }

  void warn(std::string text) { host_.report(true, std::move(text)); }
  void log(std::string text) { host_.report(false, std::move(text)); }

  // State worth keeping across runs of this node in one session (e.g. a
  // factorization), keyed by everything it depends on; make() builds it on a
  // miss. A node keeps its four most recently used keys. Use one T per key.
  template <class T, class Make>
  std::shared_ptr<T> scratch(std::uint64_t key, Make make) {
    return std::static_pointer_cast<T>(
        host_.scratch(key, [&]() -> std::shared_ptr<void> { return make(); }));
  }

  // State of a sink that gathers the frames of one evaluation in order (a
  // video writer): made at the first frame this node runs, handed back at every
  // later frame of the same evaluation, and destroyed when the evaluation ends.
  // The node finishes its work at time().last; if the evaluation stops early
  // (cancelled, failed) the state is destroyed unfinished, so its destructor
  // must clean up (remove a temporary file).
  template <class T, class Make>
  std::shared_ptr<T> sequence_state(Make make) {
    return std::static_pointer_cast<T>(
        host_.sequence_state([&]() -> std::shared_ptr<void> { return make(); }));
  }

  const std::filesystem::path& graph_dir() const { return graph_dir_; }
  const std::filesystem::path& output_dir() const { return output_dir_; }

  // The pixels to compute, for a node declared set_pixel_independent(); the
  // whole image for every other node and in a run that is not split.
  PixelRegion region() const { return host_.pixel_region(); }
  // Split by samples (region().by_samples): replaces `values` on every part
  // with their sum over the parts. Call it from the node's calling thread,
  // at the same points on every part. `work`: what this part did since its
  // last sum (a path tracer: the samples it took), for the engine's report
  // of what each part did. Does nothing in a run that is not split.
  void sum_over_parts(double* values, std::size_t count, double work) { host_.sum_over_parts(values, count, work); }
  // Dealt as parts ask (region().dealt()): the next slot of this pass for
  // this part to trace, or -1 when every slot of the pass is taken (then
  // sum_over_parts ends the pass). Call it from the node's calling thread.
  int take_slot() { return host_.take_slot(); }

  // Declares that the result depends on a file the node found by itself (a
  // material library or texture named inside a scene file). Files given to
  // input_file inputs, literal or linked, are declared by the engine. The
  // engine keeps each file's size and modification time with the result (in
  // memory and on disk) and recomputes when one of them changed.
  void depends_on_file(const std::filesystem::path& path) { host_.depends_on_file(path); }

  // An intermediate value of an output while the node runs (a path tracer's
  // image after each pass of samples), for whoever watches the evaluation
  // (the editor's viewer, `loom run --preview`). make() builds the value and
  // is called only when someone listens, so publishing costs nothing
  // otherwise. A partial value is shown, never cached, saved by a sink or
  // passed downstream: only Outputs::set makes a result. Call it from the
  // node's calling thread, between passes, never from inside parallel_for.
  template <class Make>
  void publish_partial(std::string_view output, Make make, const PartialInfo& info) {
    if (!host_.partial_wanted()) return;
    using T = std::decay_t<decltype(make())>;
    host_.publish_partial(output, Value::make<T>(make()), info);
  }
  bool partial_wanted() const { return host_.partial_wanted(); }

 private:
  NodeHost& host_;
  const std::string& node_id_;
  std::uint64_t seed_;
  std::optional<std::mt19937_64> rng_;
  const std::filesystem::path& graph_dir_;
  const std::filesystem::path& output_dir_;
  FrameTime time_;
};

}  // namespace loom
