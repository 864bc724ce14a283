// Plugin author API. The one error type a node throws. Its message is for the user: say what is
// wrong and what to do ("mask is empty: nothing to blend"). The engine adds the
// node id, so a node never repeats it.
#pragma once

#include <stdexcept>
#include <string>

#include "loom/export.hpp"

namespace loom {

class LOOM_API Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thrown by Context::check_cancelled(); the engine reports the node as failed
// with "cancelled" and never caches its result.
class LOOM_API Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

}  // namespace loom
