// hunav_manager: moves the simulated people. Answers the world's step requests over LCM.
#include "hunav/manager/manager_node.hpp"
#include "hunav/signals.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"hunav_manager: the human model (social forces and behaviors). Answers STEP_REQUEST with "
               "STEP_REPLY (lcmtypes/README.md)."};
  std::string url;
  int episodes = 0;
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL, else udpm on this host only)");
  app.add_option("--episodes", episodes, "exit after this many episode END events (0: run until SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);

  const auto& stop = hunav::installStopSignals();
  try {
    lcm::LCM lcm(hunav::resolveLcmUrl(url));
    hunav::Bus bus(lcm);
    hunav::manager::ManagerNode node(bus);
    std::cout << "ready" << std::endl;
    while (!stop.load() && (episodes == 0 || node.episodesEnded() < static_cast<std::uint64_t>(episodes)))
      bus.handleFor(std::chrono::milliseconds(100));
    std::cerr << "hunav_manager: " << node.stepsComputed() << " steps, " << node.repliesResent()
              << " resent replies, " << bus.droppedMessages() << " dropped messages\n";
  } catch (const std::exception& e) {
    std::cerr << "hunav_manager: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
