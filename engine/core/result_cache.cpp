// What is kept and where: the memory cache (ordinary results for two frames,
// simulation states under a budget, each chain's latest state) and the
// persistent disk cache (results slow to compute and quick to read back).
#include <sys/stat.h>

#include <algorithm>

#include "computation_hash.hpp"
#include "evaluation.hpp"
#include "graph_time.hpp"
#include "loom/disk_cache.hpp"

namespace loom::detail {

namespace {

// Memory held by a simulation state, for the budget.
std::size_t bytes_of(const std::vector<Value>& values) {
  std::size_t total = 0;
  for (const Value& v : values) {
    if (!v) continue;
    if (v.type()->bytes) {
      total += v.type()->bytes(v.data());
    } else if (v.type()->storable()) {
      ByteWriter w;
      v.type()->write(v.data(), w);
      total += w.buffer().size();
    } else {
      total += 1024;
    }
  }
  return total;
}

}  // namespace

FileStamp stamp_of(const std::string& path) {
  FileStamp f;
  f.path = path;
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) {
    f.size = static_cast<std::int64_t>(st.st_size);
    f.mtime = static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
  }
  return f;
}

bool still_current(const std::vector<FileStamp>& files) {
  for (const FileStamp& f : files)
    if (!(stamp_of(f.path) == f)) return false;
  return true;
}

json stamps_to_json(const std::vector<FileStamp>& files) {
  json j = json::array();
  for (const FileStamp& f : files) j.push_back({f.path, f.size, f.mtime});
  return json{{"files", j}};
}

std::optional<std::vector<FileStamp>> stamps_from_json(const json& j) {
  if (!j.is_object() || !j.contains("files") || !j["files"].is_array()) return std::nullopt;
  std::vector<FileStamp> files;
  for (const json& f : j["files"]) {
    if (!f.is_array() || f.size() != 3 || !f[0].is_string() || !f[1].is_number_integer() ||
        !f[2].is_number_integer())
      return std::nullopt;
    files.push_back({f[0].get<std::string>(), f[1].get<std::int64_t>(), f[2].get<std::int64_t>()});
  }
  return files;
}

void NodeState::add_files(const std::vector<FileStamp>& more) {
  if (more.empty()) return;
  std::lock_guard lock(files_mutex);
  for (const FileStamp& f : more)
    if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
}

// The memory entry of `hash`, or a simulation chain's latest state when it is
// that hash, and only while the files it depends on are unchanged: the lookup
// both kept() and cache_find() make. The caller holds the cache mutex; `touch`
// marks the entry used in this frame.
Evaluation::MemoryHit Evaluation::memory_entry(const NodeState& s, std::uint64_t hash, bool touch) {
  auto it = session.cache.find(hash);
  if (it != session.cache.end()) {
    if (!still_current(it->second.files)) return {};
    if (touch) it->second.generation = session.generation;
    return {&it->second.outputs, &it->second.files, it->second.seconds};
  }
  if (!s.type->spec.simulation()) return {};
  auto latest = session.latest_states.find(s.chain);
  if (latest == session.latest_states.end() || state_hash(s.chain, latest->second.frame) != hash ||
      !still_current(latest->second.files))
    return {};
  if (touch) latest->second.generation = session.generation;
  return {&latest->second.outputs, &latest->second.files, latest->second.seconds};
}

// A disk entry is counted as kept without reading it; whether its files are
// unchanged is known only when cache_find reads it (a stale one is then a
// miss, and the node runs its inputs as for a corrupt entry).
Kept Evaluation::kept(const NodeState& s, std::uint64_t hash) {
  {
    std::lock_guard lock(session.cache_mutex);
    if (memory_entry(s, hash, false).outputs) return Kept::memory;
  }
  DiskCache* disk = options.disk_cache;
  return disk && disk->contains(disk->key(hash, s.type->spec.build)) ? Kept::disk : Kept::nowhere;
}

// On disk an entry holds the outputs, then one Json value with the files'
// stamps (stamps_to_json) and the seconds computing the result took.
std::optional<Evaluation::Found> Evaluation::cache_find(const NodeState& s, std::uint64_t hash) {
  {
    std::lock_guard lock(session.cache_mutex);
    if (auto hit = memory_entry(s, hash, true); hit.outputs) return Found{*hit.outputs, *hit.files, hit.seconds, false};
  }
  if (!options.disk_cache) return std::nullopt;
  const TypeInfo& stamps_type = type_of<json>();  // registered before the entry names it
  std::string problem;
  auto values = options.disk_cache->load(options.disk_cache->key(hash, s.type->spec.build), &problem);
  if (!problem.empty() && options.observer) options.observer->node_message(s.node->id, true, problem);
  const auto& outputs = s.type->spec.outputs;
  if (!values || values->size() != outputs.size() + 1 || values->back().type()->storage != stamps_type.storage) return std::nullopt;
  auto files = stamps_from_json(values->back().as<json>());
  if (!files || !still_current(*files)) return std::nullopt;
  const json& kept_with = values->back().as<json>();
  if (!kept_with.contains("seconds") || !kept_with["seconds"].is_number()) return std::nullopt;
  const double seconds = kept_with["seconds"].get<double>();
  values->pop_back();
  for (std::size_t o = 0; o < outputs.size(); ++o)
    if (!is_any(*outputs[o].type) && (*values)[o].type()->storage != outputs[o].type->storage)
      return std::nullopt;
  std::lock_guard lock(session.cache_mutex);
  auto& entry = session.cache[hash];
  entry.outputs = *values;
  entry.files = *files;
  entry.seconds = seconds;
  entry.generation = session.generation;
  entry.state = s.type->spec.simulation();
  entry.bytes = entry.state ? bytes_of(entry.outputs) : 0;
  return Found{std::move(*values), std::move(*files), entry.seconds, true};
}

// Keeps a result that just ran: in memory, and on disk when DiskCache's rule
// says reading it back beats computing it again (for a simulation: the steps
// since its last state on disk), per frame and over the frames of the run.
void Evaluation::cache_put(NodeState& s, double seconds) {
  const bool simulation = s.type->spec.simulation();
  {
    std::lock_guard lock(session.cache_mutex);
    auto& entry = session.cache[s.hash];
    entry.outputs = s.outputs;
    entry.files = s.files;
    entry.seconds = seconds;
    entry.generation = session.generation;
    entry.state = simulation;
    entry.bytes = simulation ? bytes_of(s.outputs) : 0;
    if (simulation) {
      auto& latest = session.latest_states[s.chain];
      if (latest.outputs.empty() || time.frame >= latest.frame) {
        latest.frame = time.frame;
        latest.outputs = s.outputs;
        latest.files = s.files;
        latest.seconds = seconds;
      }
      latest.generation = session.generation;
    }
  }
  DiskCache* disk = options.disk_cache;
  if (!disk) return;
  double slow = seconds;
  if (simulation) {
    std::lock_guard lock(session.cache_mutex);
    slow = session.unsaved_seconds[s.chain] += seconds;
  }
  const int frames = s.time_dependent ? time.last - time.first + 1 : 1;  // a result like it at each frame
  std::vector<Value> stored = s.outputs;
  json kept_with = stamps_to_json(s.files);
  kept_with["seconds"] = seconds;
  stored.push_back(Value::make<json>(std::move(kept_with)));
  if (disk->store(disk->key(s.hash, s.type->spec.build), stored, slow, frames) > 0 && simulation) {
    std::lock_guard lock(session.cache_mutex);
    session.unsaved_seconds[s.chain] = 0;
  }
}

// Ordinary entries live while used in one of the last two frames; simulation
// states live under the budget, least recently used out first; a chain's
// latest state lives while the chain was used in one of the last two frames.
void evict(Session::State& st, std::size_t state_budget) {
  std::lock_guard lock(st.cache_mutex);
  for (auto it = st.latest_states.begin(); it != st.latest_states.end();) {
    if (it->second.generation + 1 < st.generation) {
      st.unsaved_seconds.erase(it->first);
      it = st.latest_states.erase(it);
    } else {
      ++it;
    }
  }
  std::vector<std::pair<std::uint64_t, std::uint64_t>> states;  // generation, hash
  std::size_t state_bytes = 0;
  for (auto it = st.cache.begin(); it != st.cache.end();) {
    if (it->second.state) {
      states.emplace_back(it->second.generation, it->first);
      state_bytes += it->second.bytes;
      ++it;
    } else {
      it = it->second.generation + 1 < st.generation ? st.cache.erase(it) : std::next(it);
    }
  }
  if (state_bytes <= state_budget) return;
  std::sort(states.begin(), states.end());
  for (const auto& [generation, hash] : states) {
    if (state_bytes <= state_budget) break;
    auto it = st.cache.find(hash);
    state_bytes -= it->second.bytes;
    st.cache.erase(it);
  }
}

}  // namespace loom::detail

namespace loom {

std::vector<int> Session::cached_frames(const Graph& graph, const std::string& node, FrameRange frames,
                                        const EvalOptions& options) {
  if (!graph.nodes.count(node)) throw Error("cached_frames: unknown node \"" + node + "\"");
  State& st = *state_;
  FrameTime time = detail::graph_time(graph);
  frames.first = std::max(frames.first, time.start);
  std::vector<int> kept;
  EvalOptions hashing = options;
  hashing.allow_outside_output = true;  // only hashed, nothing is written
  // Kept at `frame`? The plan at that frame gives the node's hash (a
  // simulation's: H(chain, frame)), looked up as evaluate() would.
  auto kept_at = [&](int frame, bool* time_dependent) {
    time.frame = frame;
    detail::Evaluation e(st, graph, hashing, time);
    e.build();
    const detail::NodeState& s = e.at(e.index.at(node));
    *time_dependent = s.time_dependent;
    return s.cacheable && e.kept(s, s.hash) != detail::Kept::nowhere;
  };
  for (int frame = frames.first; frame <= frames.last; ++frame) {
    bool time_dependent = true;
    const bool here = kept_at(frame, &time_dependent);
    if (!time_dependent) {  // one result shared by every frame
      if (here)
        for (int f = frames.first; f <= frames.last; ++f) kept.push_back(f);
      return kept;
    }
    if (here) kept.push_back(frame);
  }
  return kept;
}

}  // namespace loom
