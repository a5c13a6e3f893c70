// hunav_planner: a robot planner process. Answers ROBOT_OBSERVATION with ROBOT_COMMAND (lockstep,
// see docs/planner_contract.md). Once subscribed, prints "ready" and publishes PLANNER_READY every 0.5 s
// (the readiness handshake); SIGINT/SIGTERM end it with exit 0.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hunav/channels.hpp"
#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/planners/planner_node.hpp"
#include "hunav/scenario.hpp"
#include "hunav/signals.hpp"

namespace {

namespace hp = hunav::planners;

// Everything the command line says.
struct Options {
  std::string planner_name = "dwb";
  std::string scenario_file;
  std::string config_file;
  std::string lcm_url;
  long long episodes = 0;
};

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--planner", o.planner_name, "planner to run, one of: " + joined(hp::plannerNames()))
      ->capture_default_str();
  app.add_option("--scenario", o.scenario_file, "scenario YAML file; its static map feeds the costmap")->required();
  app.add_option("--config", o.config_file,
                 "planner parameters (YAML): sections costmap, global_planner and dwb (every planner), plus "
                 "scl (scl) or sfw (sfw); a key left out keeps its default. planners/config/<planner>.yaml "
                 "lists every key with its default and meaning");
  app.add_option("--lcm-url", o.lcm_url,
                 "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(hunav::kDefaultLcmUrl) + ")");
  app.add_option("--episodes", o.episodes,
                 "exit after this many episodes have ended (EPISODE_EVENT END); 0 = run until signalled")
      ->check(hunav::cli::nonNegativeInteger())
      ->capture_default_str();
}

// The planner chosen by name, on the scenario's static map and the --config parameters.
std::unique_ptr<hp::Planner> plannerFor(const Options& o) {
  const hunav::Scenario scenario = hunav::loadScenario(o.scenario_file);
  std::optional<hunav::YamlReader> config;
  if (!o.config_file.empty()) config.emplace(o.config_file);
  return hp::createPlanner(o.planner_name, scenario, config ? &*config : nullptr);
}

int run(const Options& o, const std::atomic<bool>& stop) {
  auto planner = plannerFor(o);
  // The kernel keeps the rest of the URL's port (a WORLD_STATE every tick) from waking this
  // process: it wakes only for its own messages. A lost observation is the lockstep protocol's
  // business (the world resends it).
  hunav::ReceiveOptions receive;
  receive.filter_unsubscribed_channels = true;
  const std::unique_ptr<hunav::Bus> bus_storage = hunav::openBus(hunav::resolveLcmUrl(o.lcm_url), receive);
  hunav::Bus& bus = *bus_storage;
  hp::PlannerNode node(bus, std::move(planner), o.planner_name);
  // The readiness handshake (docs/planner_contract.md, "Readiness"): subscribed now, so announce it,
  // and keep announcing it (a world started later waits for one before its first episode).
  const auto period = std::chrono::milliseconds(hunav::channels::kPlannerReadyPeriodMs);
  auto last_announce = std::chrono::steady_clock::now();
  node.announce();
  std::cout << "ready" << std::endl;

  while (!stop.load() && (o.episodes == 0 || node.episodesEnded() < o.episodes)) {
    bus.handleFor(std::chrono::milliseconds(100));
    if (const auto now = std::chrono::steady_clock::now(); now - last_announce >= period) {
      node.announce();
      last_announce = now;
    }
  }

  std::cerr << "hunav_planner: " << node.plansComputed() << " plans, " << node.repliesResent() << " resent replies, "
            << bus.droppedMessages() << " dropped messages\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "HuNav-LCM robot planner: answers each robot observation (channel ROBOT_OBSERVATION) with a "
      "velocity command (ROBOT_COMMAND) echoing its seq. Prints 'ready' on stdout once subscribed. "
      "Exit codes: 0 done or signalled, 1 runtime error, 2 bad input (file, flag or parameter)."};
  Options o;
  addOptions(app, o);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  if (!hp::hasPlanner(o.planner_name)) {
    std::cerr << "--planner: unknown planner '" << o.planner_name << "' (known: " << joined(hp::plannerNames())
              << ")\n";
    return hunav::kExitBadInput;
  }
  const auto& stop = hunav::installStopSignals();
  return hunav::cli::run("hunav_planner", [&] { return run(o, stop); });
}
