// hunav_manager: moves the simulated people. Answers the world's step requests over LCM.
#include <iostream>
#include <optional>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/manager/manager_node.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/signals.hpp"
#include "hunav/thread_pool.hpp"

namespace {

// Everything the command line says.
struct Options {
  std::string lcm_url;
  std::string scenario_file;
  std::string tree_folder;
  std::string people_model;
  int episodes = 0;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--lcm-url", o.lcm_url, "LCM URL (default: $LCM_DEFAULT_URL, else udpm on this host only)");
  app.add_option("--scenario", o.scenario_file,
                 "scenario YAML: its human model (people.obstacle_points, people.navigation: routes over its map) and "
                 "every agent's behavior tree, loaded at start (a bad one: exit 2 before anything runs); without it, "
                 "people walk straight at their goals and every obstacle point sent adds its force");
  app.add_option("--people-model", o.people_model,
                 "the model every person walks with, whatever the scenario says: sfm (HuNavSim's social force model, "
                 "the default), sfm_calibrated, orca, orca_calibrated, ttc, ttc_calibrated, or a parameter file "
                 "(docs/people_models.md)");
  app.add_option("--tree-folder", o.tree_folder,
                 "a folder of behavior tree files: a step request may name one of them (relative to the folder) "
                 "besides the scenario's trees. A request naming any other file, or a bad one, is dropped and "
                 "counted: the manager opens no other path a message names")
      ->check(CLI::ExistingDirectory);
  app.add_option("--episodes", o.episodes,
                 "exit after this many episode END events (0: run until SIGINT/SIGTERM, and, with channel_ports=1, "
                 "listen to nothing but STEP_REQUEST on its own port: cheaper per tick)")
      ->check(hunav::cli::nonNegativeInteger());
}

int run(const Options& o, const std::atomic<bool>& stop) {
  std::optional<hunav::Scenario> scenario;
  if (!o.scenario_file.empty()) scenario = hunav::loadScenario(o.scenario_file);
  if (scenario && !o.people_model.empty()) hunav::overridePeopleModel(*scenario, o.people_model);
  // Without a scenario: the model for everybody (a bad name or file: exit 2 before "ready").
  std::optional<hunav::MotionModel> everyone;
  if (!scenario && !o.people_model.empty())
    everyone = hunav::resolveMotionModel(o.people_model, "", "", 0, "--people-model");
  // With --episodes it hears EPISODE_EVENT on the URL's port: the kernel keeps the world states
  // sent there every tick from waking it.
  hunav::ReceiveOptions receive;
  receive.filter_unsubscribed_channels = true;
  const std::unique_ptr<hunav::Bus> bus_storage = hunav::openBus(hunav::resolveLcmUrl(o.lcm_url), receive);
  hunav::Bus& bus = *bus_storage;
  hunav::ThreadPool threads(hunav::ThreadPool::forThisMachine(0));  // large crowds: a helper
  hunav::manager::ManagerNode node(bus, &threads, o.episodes > 0);
  // The scenario's human model (obstacle points, routes); a bad tree file: exit 2 before "ready".
  if (scenario) node.manager().useScenario(*scenario);
  if (everyone) node.manager().setPeopleModels(*everyone);
  if (!o.tree_folder.empty()) node.manager().setTreeFolder(o.tree_folder);
  std::cout << "ready" << std::endl;
  while (!stop.load() && (o.episodes == 0 || node.episodesEnded() < static_cast<std::uint64_t>(o.episodes)))
    bus.handleFor(std::chrono::milliseconds(100));
  std::cerr << "hunav_manager: " << node.stepsComputed() << " steps, " << node.repliesResent() << " resent replies, "
            << bus.droppedMessages() << " dropped messages\n";
  if (node.requestDrops().count > 0)
    std::cerr << "hunav_manager: " << node.requestDrops().count
              << " step requests dropped, the last: " << node.requestDrops().last_reason << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_manager: the human model (social forces and behaviors). Answers STEP_REQUEST with "
      "STEP_REPLY (lcmtypes/README.md)."};
  Options o;
  addOptions(app, o);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  const auto& stop = hunav::installStopSignals();
  return hunav::cli::run("hunav_manager", [&] { return run(o, stop); });
}
