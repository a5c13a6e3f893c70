#pragma once
// The planner interface and the registry the hunav_planner process picks planners from by name
// (Menge style). A planner turns one observation into one velocity command.
#include <functional>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <memory>
#include <string>
#include <vector>

#include "hunav/scenario.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav::planners {

class Planner {
 public:
  virtual ~Planner() = default;
  // The command for this observation. Called once per observation, in order; the result echoes
  // the observation's utime, seq and episode.
  virtual robot_command_t plan(const robot_observation_t& obs) = 0;
  // Forgets everything learnt in the episode (a new episode starts). The static map stays.
  virtual void reset();
};

// Builds a planner for a scenario's static map. `config` is the --config file (null: defaults);
// a factory reads its own sections from it and throws ConfigError on bad values.
using PlannerFactory = std::function<std::unique_ptr<Planner>(const Scenario& scenario, const YamlReader* config)>;

// Adds (or replaces) a planner under `name`. The built-in planners are registered from the start.
void registerPlanner(const std::string& name, PlannerFactory factory);
bool hasPlanner(const std::string& name);
std::vector<std::string> plannerNames();  // sorted
// Throws std::invalid_argument for an unknown name.
std::unique_ptr<Planner> createPlanner(const std::string& name, const Scenario& scenario,
                                       const YamlReader* config = nullptr);

// A command of (0, 0) answering `obs` (echoes utime, seq, episode).
robot_command_t stopCommand(const robot_observation_t& obs);

}  // namespace hunav::planners
