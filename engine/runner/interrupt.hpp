// Ctrl-C and SIGTERM (Slurm's scancel) for the runner's front ends: the first
// sets the flag that cancels evaluation cooperatively (the run then exits 130
// with no partial file), a second leaves at once with 130.
#pragma once

#include <atomic>

namespace loom::runner {

std::atomic<bool>& interrupt_flag();
void catch_interrupts();

}  // namespace loom::runner
