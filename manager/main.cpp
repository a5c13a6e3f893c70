// hunav_manager: moves the simulated people. Answers the world's step requests over LCM.
#include <iostream>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/signals.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_manager: the human model (social forces and behaviors). Answers STEP_REQUEST with "
      "STEP_REPLY (lcmtypes/README.md)."};
  std::string url;
  int episodes = 0;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL, else udpm on this host only)");
  app.add_option("--episodes", episodes, "exit after this many episode END events (0: run until SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;

  const auto& stop = hunav::installStopSignals();
  return hunav::cli::run("hunav_manager", [&] {
    lcm::LCM lcm(hunav::resolveLcmUrl(url));
    hunav::Bus bus(lcm);
    hunav::manager::ManagerNode node(bus);
    std::cout << "ready" << std::endl;
    while (!stop.load() && (episodes == 0 || node.episodesEnded() < static_cast<std::uint64_t>(episodes)))
      bus.handleFor(std::chrono::milliseconds(100));
    std::cerr << "hunav_manager: " << node.stepsComputed() << " steps, " << node.repliesResent() << " resent replies, "
              << bus.droppedMessages() << " dropped messages\n";
    return 0;
  });
}
