// hunav_planner: a robot planner process. Answers ROBOT_OBSERVATION with ROBOT_COMMAND (lockstep,
// see docs/planner_contract.md). Once subscribed, prints "ready" and publishes PLANNER_READY every 0.5 s
// (the readiness handshake); SIGINT/SIGTERM end it with exit 0.
#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>
#include <optional>

#include "hunav/channels.hpp"
#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/planner_node.hpp"
#include "hunav/scenario.hpp"
#include "hunav/signals.hpp"

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  namespace hp = hunav::planners;
  CLI::App app{
      "HuNav-LCM robot planner: answers each robot observation (channel ROBOT_OBSERVATION) with a "
      "velocity command (ROBOT_COMMAND) echoing its seq. Prints 'ready' on stdout once subscribed. "
      "Exit codes: 0 done or signalled, 1 runtime error, 2 bad input (file, flag or parameter)."};
  std::string planner_name = "dwb";
  std::string scenario_file;
  std::string config_file;
  std::string lcm_url;
  long long episodes = 0;
  app.add_option("--planner", planner_name, "planner to run, one of: " + joined(hp::plannerNames()))
      ->capture_default_str();
  app.add_option("--scenario", scenario_file, "scenario YAML file; its static map feeds the costmap")->required();
  app.add_option("--config", config_file,
                 "planner parameters (YAML): sections costmap, global_planner and dwb (every planner), plus "
                 "scl (scl) or sfw (sfw); a key left out keeps its default. planners/config/<planner>.yaml "
                 "lists every key with its default and meaning");
  app.add_option("--lcm-url", lcm_url,
                 "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(hunav::kDefaultLcmUrl) + ")");
  app.add_option("--episodes", episodes,
                 "exit after this many episodes have ended (EPISODE_EVENT END); 0 = run until signalled")
      ->check(hunav::cli::nonNegativeInteger())
      ->capture_default_str();
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;

  if (!hp::hasPlanner(planner_name)) {
    std::cerr << "--planner: unknown planner '" << planner_name << "' (known: " << joined(hp::plannerNames()) << ")\n";
    return hunav::kExitBadInput;
  }
  const auto& stop = hunav::installStopSignals();
  return hunav::cli::run("hunav_planner", [&] {
    const hunav::Scenario scenario = hunav::loadScenario(scenario_file);
    std::optional<hunav::YamlReader> config;
    if (!config_file.empty()) config.emplace(config_file);
    auto planner = hp::createPlanner(planner_name, scenario, config ? &*config : nullptr);

    // The kernel keeps the rest of the URL's port (a WORLD_STATE every tick) from waking this
    // process: it wakes only for its own messages. A lost observation is the lockstep protocol's
    // business (the world resends it).
    hunav::ReceiveOptions receive;
    receive.filter_unsubscribed_channels = true;
    const std::unique_ptr<hunav::Bus> bus_storage = hunav::openBus(hunav::resolveLcmUrl(lcm_url), receive);
    hunav::Bus& bus = *bus_storage;
    hp::PlannerNode node(bus, std::move(planner), planner_name);
    // The readiness handshake (docs/planner_contract.md, "Readiness"): subscribed now, so announce it,
    // and keep announcing it (a world started later waits for one before its first episode).
    const auto period = std::chrono::milliseconds(hunav::channels::kPlannerReadyPeriodMs);
    auto last_announce = std::chrono::steady_clock::now();
    node.announce();
    std::cout << "ready" << std::endl;

    while (!stop.load() && (episodes == 0 || node.episodesEnded() < episodes)) {
      bus.handleFor(std::chrono::milliseconds(100));
      if (const auto now = std::chrono::steady_clock::now(); now - last_announce >= period) {
        node.announce();
        last_announce = now;
      }
    }

    std::cerr << "hunav_planner: " << node.plansComputed() << " plans, " << node.repliesResent() << " resent replies, "
              << bus.droppedMessages() << " dropped messages\n";
    return 0;
  });
}
