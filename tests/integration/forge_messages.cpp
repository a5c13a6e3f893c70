// forge_messages URL SECONDS SEED: publishes forged messages (forged_messages.hpp) on the LCM bus at
// URL, one every 2 ms of wall clock once the run's first world state was heard, until SIGTERM or for
// SECONDS at most; then prints how many of each kind it sent. The lockstep test of issue 31
// (forged_messages_lockstep.sh) runs it beside a run in a private network namespace.
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <string>

#include "forged_messages.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/signals.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: forge_messages URL SECONDS SEED\n";
    return 2;
  }
  const auto& stop = hunav::installStopSignals();
  const std::unique_ptr<hunav::Bus> bus = hunav::openBus(argv[1]);
  hunav::testing::Forger forger(*bus, std::strtoull(argv[3], nullptr, 10));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(std::atoi(argv[2]));
  std::cout << "ready" << std::endl;
  auto next = std::chrono::steady_clock::now();
  while (!stop.load() && std::chrono::steady_clock::now() < deadline) {
    bus->handleFor(std::chrono::milliseconds(1));
    if (std::chrono::steady_clock::now() < next) continue;
    next += std::chrono::milliseconds(2);
    forger.forgeOne();
  }
  int total = 0;
  for (int k = 0; k < hunav::testing::kForgeryKinds; ++k) {
    std::cout << hunav::testing::forgeryName(static_cast<hunav::testing::Forgery>(k)) << ": " << forger.counts()[k]
              << "\n";
    total += forger.counts()[k];
  }
  std::cout << "forged " << total << " messages" << std::endl;
  return 0;
}
