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
                               std::uint64_t run_salt);

}  // namespace loom::detail
