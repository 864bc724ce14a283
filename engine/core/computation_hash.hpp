// Internal: the computation hash, the one rule that decides what is reused.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "evaluation.hpp"

namespace loom::detail {

// The hash of node `s`, given the hashes already computed for its upstream
// nodes. See computation_hash.cpp for the rule.
std::uint64_t computation_hash(const NodeState& s, const std::vector<std::unique_ptr<NodeState>>& nodes,
                               std::uint64_t run_salt, const FrameTime& time);
// A simulation's state at `frame`: H(chain, frame), where the chain is the
// node's computation hash at the start frame.
std::uint64_t state_hash(std::uint64_t chain, int frame);

}  // namespace loom::detail
