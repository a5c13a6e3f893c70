#pragma once
// Planners on generated scenarios (hunav_generate's library, generator/README.md): one episode of a
// generated scenario with a planner, in this process, and what came of it (the goal, the time,
// collisions, who stood frozen); the table of such runs per planner and their failures by cause.
// Shared by the generated-scenario test (tests/integration/test_generated_scenarios.cpp) and
// bench_generated (bench/).
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/generator/generator.hpp"

namespace hunav::testing {

struct GeneratedRun {
  std::uint64_t seed = 0;
  std::string planner;
  std::string layout;               // of the scenario (generator's report)
  double route_length = 0.0;        // m, the robot's likeliest route
  std::string status, reason;       // the episode's end
  double sim_time = 0.0;            // s
  double time_limit = 0.0;          // s
  double path_length = 0.0;         // m the robot drove
  int robot_person_collisions = 0;  // robot_on_person + person_on_robot collisions (the metrics)
  double longest_frozen = 0.0;      // s, the longest anyone stood frozen (FrozenPeople)
  int frozen_people = 0;            // people frozen for kFrozenLimit s or more
  double wall_time = 0.0;           // s
  bool reached() const { return status == "goal_reached"; }
};

// Runs the generated scenario `scenario` (its file and the generator's report) with `planner`,
// results (states.csv at `sample_rate` Hz) into `out`, the planner configured by the YAML file
// `planner_config` (empty: its defaults). `stop` (optional): set, the episode ends at once with
// status `interrupted` (a run that does not count).
GeneratedRun runGenerated(const generator::GeneratedScenario& scenario, const std::string& planner,
                          const std::filesystem::path& out, double sample_rate = 10.0,
                          const std::atomic<bool>* stop = nullptr, const std::string& planner_config = "");

// Per planner: runs, reached (%), mean and maximum time to the goal of those that reached it, stuck,
// time_limit, runs with a robot-person collision (and their count), runs with someone frozen 20 s
// or more, the longest freeze. A Markdown table.
std::string runTable(const std::vector<GeneratedRun>& runs);
// Every run that did not reach its goal or froze someone, grouped by cause (status; frozen), one
// line each: seed, layout, planner, what happened. Markdown.
std::string failuresByCause(const std::vector<GeneratedRun>& runs);
// One CSV row per run (header first).
std::string runsCsv(const std::vector<GeneratedRun>& runs);

}  // namespace hunav::testing
