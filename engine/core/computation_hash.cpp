// The computation hash (Gaffer's contract): a result is reused exactly when
// this hash is equal, so everything a node's result depends on enters it:
//
//   hash = H(node type name, node type version, the plugin's build, seed,
//            for each declared input: its name, how it is bound, and
//              a literal: its value (and, for an input file, its size and mtime)
//              a link:    the upstream node's hash and which output,
//            for a nondeterministic node: a salt new at every evaluation,
//            for a time-dependent node: the frame, start frame and rate)
//
// Only a node that reads time has the frame in its own hash; a node depending
// on one has it through the upstream hash. Every other result is the same at
// every frame, so it is computed once and shared.
//
// A simulation's state at frame f is H(chain, f), where the chain is the
// node's hash at the start frame (its initial state, parameters, start and
// rate, but not the frame): a parameter change gives a new chain and so new
// states at every frame; a change downstream leaves the chain alone.
//
// The seed (graph seed + the node's own id where it is written, "render" for
// "look.render") is in it because any node may draw from ctx.rng(): two nodes
// with equal inputs but different ids may differ.
#include "computation_hash.hpp"

namespace loom::detail {
namespace {

// A literal input file enters by its stamp (result_cache.cpp's stamp_of), the
// rule that also decides whether a kept result is still current.
void hash_file_stamp(Hasher& h, const std::string& path) {
  const FileStamp f = stamp_of(path);
  h.pod(f.size).pod(f.mtime);
}

}  // namespace

std::uint64_t computation_hash(const NodeState& s, const std::vector<std::unique_ptr<NodeState>>& nodes,
                               std::uint64_t run_salt, const FrameTime& time) {
  const NodeSpec& spec = s.type->spec;
  Hasher h;
  // The build (NodeSpec::build) too: a plugin rebuilt and reloaded in the
  // editor serves no result of its old build, nor does what it feeds.
  h.str(spec.name).pod(spec.version).pod(spec.build).pod(s.seed);
  for (std::size_t i = 0; i < s.inputs.size(); ++i) {
    const auto& b = s.inputs[i];
    h.str(spec.inputs[i].name).pod(static_cast<int>(b.kind));
    if (b.kind == NodeState::Binding::literal && b.iteration_hash != 0) {
      h.pod(b.iteration_hash);  // a value Repeat gives stands for the computation that made it
    } else if (b.kind == NodeState::Binding::literal) {
      hash_json(h, b.literal_value.to_json());
      if (spec.inputs[i].role == InputRole::input_file) hash_file_stamp(h, b.literal_value.as<std::string>());
    } else if (b.kind == NodeState::Binding::link) {
      h.pod(nodes[b.upstream]->hash).pod(b.output);
    }
  }
  if (spec.nondeterministic) h.pod(run_salt);
  if (spec.simulation()) h.pod(time.start).pod(time.fps);  // the frame enters through state_hash
  else if (spec.time_dependent) h.pod(time.frame).pod(time.start).pod(time.fps);
  return h.digest();
}

std::uint64_t state_hash(std::uint64_t chain, int frame) {
  return Hasher(chain).str("simulation state").pod(frame).digest();
}

}  // namespace loom::detail
