#include "hunav/planners/planner.hpp"

#include <map>
#include <stdexcept>

#include "dwb_planner.hpp"
#include "scl_planner.hpp"
#include "sfw_planner.hpp"

namespace hunav::planners {

void Planner::reset() {}

namespace {
// The built-in planners; another one is a line here (or a registerPlanner() call before use).
std::map<std::string, PlannerFactory>& registry() {
  static std::map<std::string, PlannerFactory> planners = {
      {"dwb", &DwbPlanner::create},
      {"scl", &SclPlanner::create},
      {"sfw", &SfwPlanner::create},
  };
  return planners;
}
}  // namespace

void registerPlanner(const std::string& name, PlannerFactory factory) { registry()[name] = std::move(factory); }

bool hasPlanner(const std::string& name) { return registry().count(name) > 0; }

std::vector<std::string> plannerNames() {
  std::vector<std::string> names;
  for (const auto& entry : registry()) names.push_back(entry.first);
  return names;
}

std::unique_ptr<Planner> createPlanner(const std::string& name, const Scenario& scenario, const YamlReader* config) {
  const auto it = registry().find(name);
  if (it == registry().end()) {
    std::string known;
    for (const std::string& n : plannerNames()) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown planner '" + name + "' (known: " + known + ")");
  }
  return it->second(scenario, config);
}

robot_command_t stopCommand(const robot_observation_t& obs) {
  robot_command_t cmd{};  // every field zero: vy too, which a differential planner never sets
  cmd.utime = obs.utime;
  cmd.seq = obs.seq;
  cmd.episode = obs.episode;
  cmd.v = 0.0;
  cmd.w = 0.0;
  return cmd;
}

}  // namespace hunav::planners
