#pragma once
// Joining a run's private network namespace (run_experiment.sh --view). A socket keeps the namespace
// it was created in: hunav_view opens its HTTP socket where the browser is (the host), then moves
// its thread into the run's namespace, where the LCM sockets it opens next see the run's bus.
#include <sys/types.h>

#include <chrono>
#include <string>

namespace hunav::view {

// Waits (up to `timeout`) until process `pid` is in another network namespace than this thread
// (run_experiment.sh re-executes itself under unshare: same PID, new namespace), then joins it
// (first its user namespace, when it has one of its own: unshare -rn). Call before starting any
// thread: setns moves only the calling thread, and threads started later inherit it. Throws
// std::runtime_error saying why.
void joinNetworkNamespaceOf(pid_t pid, std::chrono::milliseconds timeout);

// True when this thread's network namespace routes multicast (224.0.0.0/4, which LCM's udpm needs;
// run_experiment.sh adds it a moment after making the namespace).
bool multicastRouted();

// True while process `pid` exists.
bool processAlive(pid_t pid);

}  // namespace hunav::view
