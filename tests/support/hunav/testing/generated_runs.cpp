#include "hunav/testing/generated_runs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "hunav/results/states_csv.hpp"
#include "hunav/runner/in_process_run.hpp"
#include "hunav/scenario.hpp"
#include "hunav/testing/frozen_people.hpp"

namespace hunav::testing {

namespace {
std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}
}  // namespace

GeneratedRun runGenerated(const generator::GeneratedScenario& scenario, const std::string& planner,
                          const std::filesystem::path& out, double sample_rate, const std::atomic<bool>* stop,
                          const std::string& planner_config) {
  Scenario s = loadScenario(scenario.scenario_file.string());
  s.evaluation_sample_rate = sample_rate;
  runner::RunOptions o;
  o.planner = planner;
  o.planner_config = planner_config;
  o.out_dir = out.string();
  o.per_tick_files = false;
  o.stop = stop;
  const auto start = std::chrono::steady_clock::now();
  const runner::RunOutcome outcome = runner::runInProcess(s, o);
  GeneratedRun r;
  r.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.seed = s.seed;
  r.planner = planner;
  r.layout = scenario.layout;
  r.route_length = scenario.route_length;
  r.status = outcome.episode.status;
  r.reason = outcome.episode.reason;
  r.sim_time = outcome.episode.sim_time;
  r.time_limit = s.time_limit;
  if (outcome.result)
    for (const auto& m : outcome.result->metrics) {
      if (m.name == "robot_on_person_collision" || m.name == "person_on_robot_collision")
        r.robot_person_collisions += static_cast<int>(std::lround(m.value));
      if (m.name == "path_length") r.path_length = m.value;
    }
  FrozenPeople frozen;
  const results::Recording rec = results::readStatesCsv(out / "states.csv");
  for (const results::Sample& sample : rec.samples())
    for (const results::EntityState& a : rec.agents(sample)) {
      frozen.add(sample.t, a.id, a.position(), a.behavior_state,
                 a.has_goal ? std::optional<Vec2>(a.goal()) : std::nullopt, a.goal_radius);
    }
  r.longest_frozen = frozen.longestSeconds();
  r.frozen_people = frozen.frozenFor();
  return r;
}

std::string runTable(const std::vector<GeneratedRun>& runs) {
  std::vector<std::string> planners;
  for (const GeneratedRun& r : runs)
    if (std::find(planners.begin(), planners.end(), r.planner) == planners.end()) planners.push_back(r.planner);
  std::ostringstream t;
  t << "| planner | runs | at the goal | time to goal, mean (max) s | stuck | time_limit | runs with a robot-person "
       "collision (collisions) | runs with someone frozen >= 20 s | longest freeze s |\n"
       "|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& p : planners) {
    int n = 0, reached = 0, stuck = 0, timeouts = 0, collided = 0, collisions = 0, frozen_runs = 0;
    double time = 0.0, slowest = 0.0, longest_freeze = 0.0;
    for (const GeneratedRun& r : runs) {
      if (r.planner != p) continue;
      ++n;
      if (r.reached()) {
        ++reached;
        time += r.sim_time;
        slowest = std::max(slowest, r.sim_time);
      }
      stuck += r.status == "stuck";
      timeouts += r.status == "time_limit";
      collided += r.robot_person_collisions > 0;
      collisions += r.robot_person_collisions;
      frozen_runs += r.frozen_people > 0;
      longest_freeze = std::max(longest_freeze, r.longest_frozen);
    }
    t << "| " << p << " | " << n << " | " << reached << " (" << fixed(100.0 * reached / std::max(n, 1), 1) << " %) | "
      << (reached > 0 ? fixed(time / reached, 1) + " (" + fixed(slowest, 1) + ")" : "-") << " | " << stuck << " | "
      << timeouts << " | " << collided << " (" << collisions << ") | " << frozen_runs << " | "
      << fixed(longest_freeze, 1) << " |\n";
  }
  return t.str();
}

std::string failuresByCause(const std::vector<GeneratedRun>& runs) {
  std::map<std::string, std::vector<const GeneratedRun*>> causes;
  for (const GeneratedRun& r : runs) {
    if (!r.reached()) causes[r.status].push_back(&r);
    if (r.frozen_people > 0) causes["someone frozen >= 20 s"].push_back(&r);
  }
  std::ostringstream t;
  if (causes.empty()) return "No failures.\n";
  for (const auto& [cause, list] : causes) {
    t << "- **" << cause << "** (" << list.size() << "):\n";
    for (const GeneratedRun* r : list)
      t << "  - seed " << r->seed << " (" << r->layout << ", route " << fixed(r->route_length, 1) << " m), "
        << r->planner << ": " << r->status << " at " << fixed(r->sim_time, 1) << " s (" << r->reason << ")"
        << (r->frozen_people > 0 ? ", longest freeze " + fixed(r->longest_frozen, 1) + " s" : "") << "\n";
  }
  return t.str();
}

std::string runsCsv(const std::vector<GeneratedRun>& runs) {
  std::ostringstream t;
  t << "seed,layout,route_length,planner,status,sim_time,time_limit,path_length,robot_person_collisions,"
       "longest_frozen,frozen_people,wall_time\n";
  for (const GeneratedRun& r : runs)
    t << r.seed << "," << r.layout << "," << fixed(r.route_length, 2) << "," << r.planner << "," << r.status << ","
      << fixed(r.sim_time, 2) << "," << fixed(r.time_limit, 1) << "," << fixed(r.path_length, 2) << ","
      << r.robot_person_collisions << "," << fixed(r.longest_frozen, 1) << "," << r.frozen_people << ","
      << fixed(r.wall_time, 3) << "\n";
  return t.str();
}

}  // namespace hunav::testing
