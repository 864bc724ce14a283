// Author and host API. "Did you mean": near names for a name that matched nothing (node types,
// inputs), so a typo gets an answer instead of a list to read.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "loom/export.hpp"

namespace loom {

// Edit distance between a and b, compared case-insensitively: inserting,
// deleting or substituting a letter, or swapping two neighbours, costs 1 each
// (Damerau's optimal string alignment: "rnu" is 1 from "run", not 2).
LOOM_API std::size_t edit_distance(std::string_view a, std::string_view b);

// Up to `limit` candidates near `name`, nearest first: a case-insensitive
// match first, then names within an edit distance of about a third of the
// name's length (at least 1, at most 3), then names that contain it or that
// it contains (case-insensitively; at least 4 letters). Duplicates are dropped.
LOOM_API std::vector<std::string> near_names(std::string_view name, const std::vector<std::string>& candidates,
                                             std::size_t limit = 3);

// The message for a node type nothing provides: the near names among the
// registry's types and those of plugins not loaded (`known_types`), where the
// engine searched, and how to make a plugin of one's own visible.
LOOM_API std::string unknown_node_type_message(const std::string& type,
                                               const std::vector<std::string>& known_types,
                                               const std::string& searched);

}  // namespace loom
