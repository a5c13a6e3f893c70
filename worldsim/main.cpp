// hunav_worldsim: the Box2D world. Owns the clock and runs episodes over LCM.
#include <iostream>

#include "hunav/cli.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/signals.hpp"
#include "hunav/worldsim/world_sim.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_worldsim: the world simulator. Runs episodes of a scenario in lockstep with the manager "
      "and the planner (lcmtypes/README.md). Exit 0: every episode ran to an end (goal reached, time "
      "limit or stuck); 1: aborted or error; 2: bad input; 130/143: interrupted by SIGINT/SIGTERM (README.md, "
      "\"Statuses and exit codes\")."};
  std::string scenario_file, url, planner = "dwb", mode = "lockstep", run_id;
  long long seed = -1;
  double duration = 0.0;
  int episodes = 1;
  double silence_limit = 1.0, startup_limit = 10.0, ready_timeout = 10.0;
  app.add_option("--scenario", scenario_file, "scenario YAML file")->required();
  app.add_option("--planner", planner, "planner name reported in events; 'none' runs without a planner");
  app.add_option("--seed", seed, "override the scenario's seed (episode k of --episodes uses seed + k - 1)")
      ->check(hunav::cli::nonNegativeInteger());
  app.add_option("--duration", duration, "override the scenario's time limit, s of simulation time")
      ->check(hunav::cli::positiveNumber());
  app.add_option("--mode", mode, "lockstep (wait for every answer) or realtime (wall-clock paced)")
      ->check(CLI::IsMember({"lockstep", "realtime"}));
  app.add_option("--run-id", run_id,
                 "run id (default <scenario>_<planner>_s<seed>); with several episodes, episode k is <run-id>_e<k>");
  app.add_option("--episodes", episodes,
                 "episodes to run back to back, each from a fresh world with the next seed and its own run id")
      ->check(hunav::cli::positiveInteger());
  // At most 1e6 s (11 days): beyond ~9.2e6 s the limit overflows as nanoseconds and aborts at once.
  app.add_option("--silence-limit", silence_limit, "abort when a component is silent this long, s (wall clock)")
      ->check(CLI::Range(1e-3, 1e6));
  app.add_option("--startup-limit", startup_limit, "the same for a component's first answer, s")
      ->check(CLI::Range(1e-3, 1e6));
  app.add_option("--planner-ready-timeout", ready_timeout,
                 "s to wait before the first episode for the planner's PLANNER_READY (docs/planner_contract.md, "
                 "\"Readiness\"); without it the episode ends at once, aborted; 0 = do not wait")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app.add_option("--lcm-url", url, "LCM URL (default: $LCM_DEFAULT_URL, else udpm on this host only)");
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;

  return hunav::cli::run("hunav_worldsim", [&] {
    // Every episode's scenario is loaded (and checked) before anything starts; the seed also draws the
    // random agent parameters, so each episode loads the file with its own seed.
    std::vector<hunav::Scenario> scenarios{hunav::cli::loadScenarioFor(scenario_file, seed, duration)};
    const auto first_seed = static_cast<long long>(scenarios.front().seed);
    for (int k = 1; k < episodes; ++k)
      scenarios.push_back(hunav::cli::loadScenarioFor(scenario_file, first_seed + k, duration));
    hunav::worldsim::WorldOptions options;
    options.planner = planner;
    options.mode = mode;
    options.run_id = run_id;
    options.silence_limit = std::chrono::milliseconds(static_cast<long>(silence_limit * 1000));
    options.startup_limit = std::chrono::milliseconds(static_cast<long>(startup_limit * 1000));
    options.planner_ready_timeout = std::chrono::milliseconds(static_cast<long>(ready_timeout * 1000));
    options.stop = &hunav::installStopSignals();
    const std::unique_ptr<hunav::Bus> bus = hunav::openBus(hunav::resolveLcmUrl(url));
    hunav::worldsim::WorldSim world(*bus, scenarios.front(), options);
    int code = 0;  // of the first episode that did not run to an end
    for (int i = 0; i < episodes && !options.stop->load(); ++i) {
      const std::string id = run_id.empty() || episodes == 1 ? run_id : run_id + "_e" + std::to_string(i + 1);
      const auto r = world.runEpisode(scenarios[static_cast<std::size_t>(i)], id);
      std::cout << "episode " << i + 1 << " (run " << r.run_id << ", seed " << r.seed << "): " << r.status << " ("
                << r.reason << "), " << r.ticks << " ticks, " << r.sim_time << " s simulated in " << r.wall_time
                << " s, " << r.collisions << " contacts, " << r.dropped_messages << " dropped messages, "
                << world.resends() << " resends so far, fingerprint " << r.fingerprint << std::endl;
      if (code == 0) code = hunav::episode_status::exitCodeFor(r.status, hunav::stopSignal());
    }
    return code;
  });
}
