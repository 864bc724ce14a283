// The record embree_ray_log.cpp writes for each ray a program hands Embree
// (the file is these records back to back, in call order, native layout).
#pragma once

#include <embree3/rtcore.h>

namespace loom::pathtrace::bench {

struct LoggedRay {
  RTCRay ray;      // as handed to Embree, before the call
  unsigned flags;  // the intersect context's flags (coherent, incoherent)
  bool shadow;     // rtcOccluded1 (otherwise rtcIntersect1)
  bool found;      // a surface hit, or a blocker found
};

}  // namespace loom::pathtrace::bench
