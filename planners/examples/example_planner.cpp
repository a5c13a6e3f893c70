// example_planner: the minimal external planner (example_planner.hpp) as a process.
// Usage: example_planner [LCM_URL] [EPISODES]
//   LCM_URL  default: $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0
//   EPISODES exit 0 after this many EPISODE_EVENT END events (default 0: run until killed)
#include "example_planner.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  const char* env = std::getenv("LCM_DEFAULT_URL");
  const std::string url = argc > 1 ? argv[1] : (env != nullptr ? env : "udpm://239.255.76.67:7667?ttl=0");
  const long episodes = argc > 2 ? std::atol(argv[2]) : 0;
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "example_planner: cannot open LCM at %s\n", url.c_str());
    return 1;
  }
  example::GoToGoalPlanner planner(lcm);
  std::printf("ready\n");
  std::fflush(stdout);
  while (episodes == 0 || planner.episodesEnded() < episodes)
    if (lcm.handleTimeout(100) < 0) return 1;
  return 0;
}
