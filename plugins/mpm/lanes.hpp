// Two doubles in one register (a GCC/Clang vector extension: SSE2 on x86-64, the
// baseline Loom is built for). Each lane does the scalar code's IEEE operation on
// one component, in the scalar code's order, so results are bit-identical to it.
#pragma once

namespace loom::mpm {

using Pair = double __attribute__((vector_size(16)));
using PairMask = long __attribute__((vector_size(16)));  // what comparing two Pairs gives

}  // namespace loom::mpm
