// bench_manager: cost of one manager step (forces + tree ticks + integration, one thread) on a
// crowd of regular people in a square hall with walls, and the error of the social-force cut-off
// against all pairs on random crowds.
//   bench_manager [--agents N] [--hall L] [--steps S] [--cutoff R] [--tolerance T] [--error]
//                 [--no-exact] [--fingerprint] [--social-only]
// --tolerance: people.force_tolerance (pairs whose force is certainly below T x the largest are
// skipped); with --error, the error of the tolerance at the cut-off against every pair within it.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "hunav/fingerprint.hpp"
#include "hunav/manager/agent_manager.hpp"
#include "people_social.hpp"  // the grid and the pair kernel (internal)

using namespace hunav;
using namespace hunav::manager;

namespace {

step_request_t crowd(int n, double hall, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0.5, hall - 0.5), ang(-kPi, kPi), speed(0.0, 1.2);
  step_request_t r{};
  r.utime = 0;
  r.seq = 1;
  r.episode = 1;
  r.dt = 0.01;
  for (int i = 0; i < n; ++i) {
    agent_state_t a{};
    a.id = i + 1;
    a.type = agent_state_t::TYPE_PERSON;
    a.behavior = agent_state_t::BEH_REGULAR;
    a.group_id = i % 10 == 0 ? i / 10 % 50 : -1;
    a.x = pos(rng);
    a.y = pos(rng);
    const double h = ang(rng), s = speed(rng);
    a.vx = s * std::cos(h);
    a.vy = s * std::sin(h);
    a.yaw = h;
    a.radius = 0.35;
    a.desired_speed = 1.2;
    a.goal_radius = 0.3;
    a.cyclic_goals = true;
    a.goals = {point2d_t{pos(rng), pos(rng)}, point2d_t{pos(rng), pos(rng)}};
    a.num_goals = 2;
    a.behavior_params.goal_force_factor = 2.0;
    a.behavior_params.obstacle_force_factor = 10.0;
    a.behavior_params.social_force_factor = 5.0;
    a.robot_in_sight = true;
    r.agents.push_back(a);
  }
  r.num_agents = n;
  r.robot = r.agents[0];
  r.robot.id = 0;
  r.robot.type = agent_state_t::TYPE_ROBOT;
  r.robot.x = r.robot.y = hall / 2;
  return r;
}

// The world's job, done here: the closest point of each wall within 3 m.
void wallPoints(step_request_t& r, double hall) {
  for (agent_state_t& a : r.agents) {
    a.obstacles.clear();
    if (a.x < 3) a.obstacles.push_back({0, a.y});
    if (a.x > hall - 3) a.obstacles.push_back({hall, a.y});
    if (a.y < 3) a.obstacles.push_back({a.x, 0});
    if (a.y > hall - 3) a.obstacles.push_back({a.x, hall});
    a.num_obstacles = static_cast<int32_t>(a.obstacles.size());
  }
}

// CPU time of this thread, s (other processes sharing the cores do not inflate it).
double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct StepTimes {
  double min_ms = 0.0;
  double median_ms = 0.0;
};

// Thread CPU time of each step: minimum and median over `steps` steps.
StepTimes timeSteps(int n, double hall, int steps, double cutoff, double tolerance) {
  AgentManager m;
  m.setSocialCutoff(cutoff);
  m.setForceTolerance(tolerance);
  step_request_t r = crowd(n, hall, 42);
  wallPoints(r, hall);
  m.step(r);  // warm-up: trees built
  std::vector<double> ms;
  step_reply_t rep;
  for (int s = 0; s < steps; ++s) {
    r.seq += 1;
    const double t0 = threadCpuSeconds();
    m.step(r, rep);  // the manager process reuses its reply the same way
    ms.push_back((threadCpuSeconds() - t0) * 1e3);
    std::swap(r.agents, rep.agents);
    r.utime = rep.utime;
    wallPoints(r, hall);
  }
  std::sort(ms.begin(), ms.end());
  return StepTimes{ms.front(), ms[ms.size() / 2]};
}

// Thread CPU time of the people-people social force alone (grid build + pair kernel) on one thread,
// minimum over `steps` repetitions on one crowd.
void timeSocialOnly(int n, double hall, int steps, double cutoff, double tolerance) {
  const step_request_t r = crowd(n, hall, 42);
  StepSnapshot snap;
  snap.request = &r;
  for (const auto& a : r.agents) snap.agents.push_back(SfmBody{a.id, -1, Vec2(a.x, a.y), Vec2(a.vx, a.vy), a.radius});
  snap.index();
  NeighborGrid grid;
  long pairs = 0;
  grid.build(snap.agents, snap.by_id, cutoff);
  grid.forEachPair(cutoff, [&](int, int) { ++pairs; });
  PeopleSocialForces forces;
  double best = 1e9;
  for (int s = 0; s < steps; ++s) {
    const double t0 = threadCpuSeconds();
    grid.build(snap.agents, snap.by_id, cutoff);
    forces.compute(snap, grid, cutoff, nullptr, tolerance);
    best = std::min(best, threadCpuSeconds() - t0);
  }
  std::printf(
      "%d agents, %.1f m hall, cut-off %.1f m, tolerance %g: %ld pairs within the cut-off, social force %.3f ms "
      "(min), %.2f ns/pair\n",
      n, hall, cutoff, tolerance, pairs, best * 1e3, best * 1e9 / static_cast<double>(pairs));
}

// Fingerprint of every agent state over `steps` steps of a crowd (mixed behaviors, groups, a moving
// robot): compares two builds bit for bit.
std::string fingerprintRun(int n, double hall, int steps, double cutoff) {
  AgentManager m;
  m.setSocialCutoff(cutoff);
  step_request_t r = crowd(n, hall, 7);
  for (std::size_t i = 0; i < r.agents.size(); ++i) {
    r.agents[i].behavior = static_cast<int8_t>(1 + i % 6);
    r.agents[i].behavior_params.dist = 4.0;
    r.agents[i].behavior_params.duration = 2.0;
    r.agents[i].behavior_params.vel = 1.0;
  }
  Fingerprint fp;
  auto add = [&](double v) { fp.add(&v, sizeof v); };
  for (int s = 0; s < steps; ++s) {
    r.robot.x = hall / 2 + 5.0 * std::cos(0.01 * s);
    r.robot.y = hall / 2 + 5.0 * std::sin(0.01 * s);
    r.robot.yaw = 0.01 * s + kPi / 2;
    wallPoints(r, hall);
    step_reply_t rep = m.step(r);
    for (const agent_state_t& a : rep.agents) {
      for (double v : {a.x, a.y, a.yaw, a.vx, a.vy, a.linear_vel, a.angular_vel}) add(v);
      fp.add(&a.behavior_state, sizeof a.behavior_state);
      fp.add(&a.num_goals, sizeof a.num_goals);
    }
    r.agents = std::move(rep.agents);
    r.utime = rep.utime;
    r.seq += 1;
  }
  return fp.hex();
}

// The error of the cut-off against all pairs, or with tolerance > 0 the error of the tolerance
// against every pair within the cut-off.
void cutoffError(double cutoff, double tolerance, int crowds, int n, double hall) {
  double sum_err = 0.0, max_err = 0.0, sum_force = 0.0, max_rel = 0.0;
  long count = 0;
  for (int k = 0; k < crowds; ++k) {
    const step_request_t r = crowd(n, hall, 1000 + static_cast<std::uint64_t>(k));
    StepSnapshot exact;
    exact.request = &r;
    for (const auto& a : r.agents)
      exact.agents.push_back(SfmBody{a.id, -1, Vec2(a.x, a.y), Vec2(a.vx, a.vy), a.radius});
    exact.index();
    StepSnapshot cut = exact;
    NeighborGrid grid;
    grid.build(cut.agents, cut.by_id, cutoff);
    computePeopleSocial(cut, grid, cutoff, nullptr, tolerance);
    if (tolerance > 0.0) computePeopleSocial(exact, grid, cutoff);  // the reference: every pair within it
    for (std::size_t i = 0; i < r.agents.size(); ++i) {
      const Vec2 fe = computeForces(exact, i, r.agents[i], nullptr, RobotAs::Ignored, 1.2).social;
      const Vec2 fc = computeForces(cut, i, r.agents[i], nullptr, RobotAs::Ignored, 1.2).social;
      const double e = (fe - fc).norm();
      sum_err += e;
      max_err = std::max(max_err, e);
      sum_force += fe.norm();
      if (fe.norm() > 0) max_rel = std::max(max_rel, e / fe.norm());
      ++count;
    }
  }
  std::printf(
      "cutoff %.1f m, tolerance %g: mean |F_soc| %.5f, mean error %.6f (%.3f%% of mean force), max error %.6f, "
      "max relative error %.2f%%\n",
      cutoff, tolerance, sum_force / count, sum_err / count, 100.0 * sum_err / sum_force, max_err, 100.0 * max_rel);
}

}  // namespace

int main(int argc, char** argv) {
  int n = 1000, steps = 200;
  double hall = 40.0, cutoff = kDefaultSocialCutoff;
  double tolerance = 0.0;
  bool error = false, exact = true, fingerprint = false, social_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] {
      return i + 1 < argc ? argv[++i] : (std::fprintf(stderr, "%s: value missing\n", a.c_str()), std::exit(2), "");
    };
    if (a == "--agents")
      n = std::atoi(next());
    else if (a == "--hall")
      hall = std::atof(next());
    else if (a == "--steps")
      steps = std::atoi(next());
    else if (a == "--cutoff")
      cutoff = std::atof(next());
    else if (a == "--tolerance")
      tolerance = std::atof(next());
    else if (a == "--error")
      error = true;
    else if (a == "--no-exact")
      exact = false;
    else if (a == "--fingerprint")
      fingerprint = true;
    else if (a == "--social-only")
      social_only = true;
    else {
      std::fprintf(stderr,
                   "usage: bench_manager [--agents N] [--hall L] [--steps S] [--cutoff R] [--tolerance T] [--error] "
                   "[--no-exact] [--fingerprint] [--social-only]\n");
      return 2;
    }
  }
  if (social_only) {
    timeSocialOnly(n, hall, steps, cutoff, tolerance);
    return 0;
  }
  if (fingerprint) {
    const std::string fp = fingerprintRun(n, hall, steps, cutoff);
    std::printf("fingerprint %s (%d agents, %d steps, cut-off %.1f m)\n", fp.c_str(), n, steps, cutoff);
    return 0;
  }
  if (error) {
    if (tolerance > 0.0)
      cutoffError(cutoff, tolerance, 5, n, hall);
    else
      for (double c : {2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 7.5, 8.0, 10.0}) cutoffError(c, 0.0, 5, n, hall);
    return 0;
  }
  const StepTimes grid = timeSteps(n, hall, steps, cutoff, tolerance);
  std::printf(
      "%d agents, %.1f x %.1f m hall, cut-off %.1f m: %.3f ms/step (min), %.3f ms/step (median), "
      "thread CPU time over %d steps\n",
      n, hall, hall, cutoff, grid.min_ms, grid.median_ms, steps);
  if (!exact) return 0;
  const int exact_steps = std::max(1, steps / (n >= 5000 ? 20 : 4));
  const StepTimes all = timeSteps(n, hall, exact_steps, 0.0, 0.0);
  std::printf("%d agents, %.1f x %.1f m hall, all pairs: %.3f ms/step (min), %.3f ms/step (median) over %d steps\n", n,
              hall, hall, all.min_ms, all.median_ms, exact_steps);
  return 0;
}
