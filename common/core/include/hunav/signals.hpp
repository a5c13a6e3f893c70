#pragma once
// SIGINT/SIGTERM set a flag that the processes' loops poll, so a run ends cleanly and keeps its data.
#include <atomic>

namespace hunav {
// Installs the handlers (idempotent) and returns the flag they set.
const std::atomic<bool>& installStopSignals();
// The signal that set the flag (SIGINT or SIGTERM), 0 before any: exit codes are 128 + it.
int stopSignal();
}  // namespace hunav
