#include "hunav/evaluator/counterfactual.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "hunav/results/states_csv.hpp"

namespace hunav::evaluator {

namespace fs = std::filesystem;

namespace {

// The goal a person walks to at a sample, as states.csv holds it (no goal: has_goal false).
bool sameGoal(const EntityState& a, const EntityState& b) {
  if (a.has_goal != b.has_goal) return false;
  return !a.has_goal || (a.goal_x == b.goal_x && a.goal_y == b.goal_y);
}

// One person's trajectory through a recording: the agent at index `i` of every sample.
struct Track {
  std::vector<double> reach_times;  // when the goal changed (time of the first sample with the next one)
  double path = 0.0;
};

Track trackOf(const Recording& r, std::size_t i) {
  Track t;
  for (std::size_t k = 1; k < r.size(); ++k) {
    const EntityState& prev = r.agents(r[k - 1])[i];
    const EntityState& now = r.agents(r[k])[i];
    t.path += (now.position() - prev.position()).norm();
    if (!sameGoal(prev, now)) t.reach_times.push_back(r[k].t);
  }
  return t;
}

}  // namespace

std::vector<PersonCounterfactual> compareWithRobotFree(const Recording& with_robot, const Recording& without_robot) {
  if (with_robot.size() != without_robot.size())
    throw std::invalid_argument(
        fmt::format("counterfactual: {} samples with the robot, {} without", with_robot.size(), without_robot.size()));
  for (std::size_t k = 0; k < with_robot.size(); ++k) {
    const Sample& a = with_robot[k];
    const Sample& b = without_robot[k];
    if (a.t != b.t)
      throw std::invalid_argument(
          fmt::format("counterfactual: sample {} at {} s with the robot, {} s without", k, a.t, b.t));
    if (a.agents_count != b.agents_count)
      throw std::invalid_argument(fmt::format("counterfactual: {} people at {} s with the robot, {} without",
                                              a.agents_count, a.t, b.agents_count));
    const auto pa = with_robot.agents(a);
    const auto pb = without_robot.agents(b);
    for (std::size_t i = 0; i < pa.size(); ++i)
      if (pa[i].id != pb[i].id)
        throw std::invalid_argument(fmt::format(
            "counterfactual: person {} of the run is {} in the robot-free run at {} s", pa[i].id, pb[i].id, a.t));
  }
  std::vector<PersonCounterfactual> people;
  if (with_robot.empty()) return people;
  const std::size_t n = with_robot.front().agents_count;
  const double end_time = with_robot.back().t;
  people.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    PersonCounterfactual& p = people[i];
    const EntityState& first = with_robot.agents(with_robot.front())[i];
    p.id = first.id;
    p.behavior = first.behavior;
    const Track w = trackOf(with_robot, i);
    const Track f = trackOf(without_robot, i);
    p.goals_with = static_cast<int>(w.reach_times.size());
    p.goals_without = static_cast<int>(f.reach_times.size());
    p.goals_missed = std::max(0, p.goals_without - p.goals_with);
    if (!f.reach_times.empty()) {
      // The k-th goal is the same goal in both runs (the same queue); a goal not reached with the robot
      // by the end of the run counts as reached at the end: a lower bound of its delay.
      const std::size_t k = f.reach_times.size() - 1;
      const double reached = k < w.reach_times.size() ? w.reach_times[k] : end_time;
      p.delay = reached - f.reach_times[k];
    }
    p.path_with = w.path;
    p.path_without = f.path;
    p.path_added = w.path - f.path;
    double sum = 0.0;
    for (std::size_t k = 0; k < with_robot.size(); ++k) {
      const EntityState& a = with_robot.agents(with_robot[k])[i];
      const EntityState& b = without_robot.agents(without_robot[k])[i];
      const double d = (a.position() - b.position()).norm();
      sum += d;
      p.max_deviation = std::max(p.max_deviation, d);
      if (k == 0) continue;
      // The change of velocity over the step is the acceleration times the step: summing the norm of
      // its difference is the integral of |a_with - a_without| over time.
      const EntityState& a0 = with_robot.agents(with_robot[k - 1])[i];
      const EntityState& b0 = without_robot.agents(without_robot[k - 1])[i];
      const Vec2 dv_with(a.vx - a0.vx, a.vy - a0.vy);
      const Vec2 dv_without(b.vx - b0.vx, b.vy - b0.vy);
      p.extra_effort += (dv_with - dv_without).norm();
    }
    p.mean_deviation = sum / static_cast<double>(with_robot.size());
    p.affected = p.max_deviation > kAffectedDeviation;
  }
  return people;
}

const std::vector<std::string>& counterfactualMetricNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& s : results::counterfactualCatalog()) n.push_back(s.name);
    return n;
  }();
  return names;
}

std::vector<MetricValue> counterfactualMetrics(const std::vector<PersonCounterfactual>& people) {
  double affected = 0.0, delay = 0.0, missed = 0.0, path = 0.0, mean_dev = 0.0, max_dev = 0.0, effort = 0.0;
  for (const PersonCounterfactual& p : people) {
    affected += p.affected ? 1.0 : 0.0;
    delay += p.delay;
    missed += p.goals_missed;
    path += p.path_added;
    mean_dev += p.mean_deviation;
    max_dev = std::max(max_dev, p.max_deviation);
    effort += p.extra_effort;
  }
  if (!people.empty()) mean_dev /= static_cast<double>(people.size());
  // In the catalogue's order (metric_catalog.hpp).
  const double values[] = {affected, delay, missed, path, mean_dev, max_dev, effort};
  const auto& specs = results::counterfactualCatalog();
  std::vector<MetricValue> out;
  for (std::size_t i = 0; i < specs.size(); ++i)
    out.push_back({specs[i].name, specs[i].unit, specs[i].kind, values[i]});
  return out;
}

void writeCounterfactualCsv(const fs::path& file, const std::vector<PersonCounterfactual>& people) {
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out),
                 "id,behavior,goals_with,goals_without,goals_missed,delay,path_with,path_without,path_added,"
                 "mean_deviation,max_deviation,extra_effort,affected\n");
  for (const PersonCounterfactual& p : people)
    fmt::format_to(std::back_inserter(out), "{},{},{},{},{},{},{},{},{},{},{},{},{}\n", p.id, int{p.behavior},
                   p.goals_with, p.goals_without, p.goals_missed, p.delay, p.path_with, p.path_without, p.path_added,
                   p.mean_deviation, p.max_deviation, p.extra_effort, p.affected ? "true" : "false");
  const fs::path tmp = file.parent_path() / ("." + file.filename().string() + ".part");
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) throw std::runtime_error("cannot write " + tmp.string());
  const bool ok = std::fwrite(out.data(), 1, out.size(), f) == out.size();
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + tmp.string());
  fs::rename(tmp, file);
}

std::vector<MetricValue> evaluateCounterfactual(const fs::path& states_csv, const RunInfo& info,
                                                const RobotFreeRun& robot_free, const fs::path& counterfactual_csv) {
  const Recording with_robot = results::readStatesCsv(states_csv);
  std::vector<double> times;
  times.reserve(with_robot.size());
  for (const Sample& s : with_robot.samples()) times.push_back(s.t);
  const Recording without_robot = robot_free(info, times);
  const std::vector<PersonCounterfactual> people = compareWithRobotFree(with_robot, without_robot);
  writeCounterfactualCsv(counterfactual_csv, people);
  return counterfactualMetrics(people);
}

}  // namespace hunav::evaluator
