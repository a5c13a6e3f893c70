#pragma once
// The robot's planners. A planner turns one observation of the robot (its state and limits, goal,
// laser scan and detected people) into one velocity command. The hunav_planner process (and
// hunav_run in one process) creates one by name from the registry below and puts it on the bus
// with a PlannerNode (planner_node.hpp); its parameters come from the --config file (params.hpp).
// The built-in planners (planners/README.md): `dwb` (a DWB-like local planner on a costmap, with an
// A* global path and recovery behaviours), `scl` (dwb plus a social costmap layer) and `sfw` (dwb
// plus a social-work critic). Their parts live in planners/src/.
#include <functional>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <memory>
#include <string>
#include <vector>

#include "hunav/geometry.hpp"
#include "hunav/scenario.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav::planners {

// What a planner implements.
class Planner {
 public:
  virtual ~Planner() = default;
  // The command for this observation. Called once per observation, in order; the result echoes
  // the observation's utime, seq and episode.
  virtual robot_command_t plan(const robot_observation_t& obs) = 0;
  // Forgets everything learnt in the episode (a new episode starts). The static map stays.
  virtual void reset();
  // True when this planner, after reset(), plans for an episode of `scenario` exactly as a planner
  // created for it would (it was built for the same static map). hunav_run --seeds then keeps it for
  // the next episode instead of building another (on a real map the costmap's static layer is most
  // of an episode's set-up). The default, false, always builds a new one.
  virtual bool servesScenario(const Scenario& /*scenario*/) const { return false; }
  // The path the planner follows after its last plan() (from near the robot to the goal), which the
  // node publishes on ROBOT_PATH for monitors (hunav_view draws it); null: none (the default).
  virtual const std::vector<Vec2>* plannedPath() const { return nullptr; }
};

// The registry (Menge style): planners are created by name (--planner dwb|scl|sfw). A new planner
// is a class deriving from Planner plus one line in the registry in src/planner.cpp (or a
// registerPlanner() call before use).

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
