// example_planner: the minimal external planner (example_planner.hpp) as a process.
// Usage: example_planner [LCM_URL] [EPISODES]
//   LCM_URL  default: LCM's own ($LCM_DEFAULT_URL, else liblcm's default: the group and port of ours)
//   EPISODES exit 0 after this many EPISODE_EVENT END events (default 0: run until killed)
#include "example_planner.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {
const char* const kUsage =
    "usage: example_planner [LCM_URL] [EPISODES]\n"
    "  LCM_URL   e.g. udpm://239.255.76.67:7667?ttl=0 (default: $LCM_DEFAULT_URL, else liblcm's default)\n"
    "  EPISODES  exit 0 after this many episodes ended (default 0: run until killed)\n"
    "Answers every ROBOT_OBSERVATION with a ROBOT_COMMAND: drive to the goal, stop when the laser\n"
    "sees something close ahead. Once subscribed prints \"ready\" and publishes PLANNER_READY every 0.5 s.\n";

int usageError(const char* what, const char* arg) {
  std::fprintf(stderr, "example_planner: %s: %s\n%s", what, arg, kUsage);
  return 2;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && (!std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help"))) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (argc > 3) return usageError("too many arguments", argv[3]);
  // LCM URLs are provider://address (udpm://, memq://, file://); anything else is a mistake.
  if (argc > 1 && std::strstr(argv[1], "://") == nullptr) return usageError("not an LCM URL", argv[1]);
  char* end = nullptr;
  const long episodes = argc > 2 ? std::strtol(argv[2], &end, 10) : 0;
  if (argc > 2 && (*end != '\0' || end == argv[2] || episodes < 0))
    return usageError("EPISODES must be a whole number >= 0", argv[2]);

  // No URL: liblcm reads $LCM_DEFAULT_URL, else uses its default (the multicast group and port ours
  // use), so a plain LCM program needs no copy of hunav's default.
  const std::string url = argc > 1 ? argv[1] : "";
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "example_planner: cannot open LCM at %s\n", url.empty() ? "the default URL" : url.c_str());
    return 1;
  }
  example::GoToGoalPlanner planner(lcm);
  planner.announceReady();
  std::printf("ready\n");
  std::fflush(stdout);
  // Announce every 0.5 s (the world waits for one before its first episode).
  auto last_announce = std::chrono::steady_clock::now();
  while (episodes == 0 || planner.episodesEnded() < episodes) {
    if (lcm.handleTimeout(100) < 0) return 1;
    if (const auto now = std::chrono::steady_clock::now(); now - last_announce >= std::chrono::milliseconds(500)) {
      planner.announceReady();
      last_announce = now;
    }
  }
  return 0;
}
