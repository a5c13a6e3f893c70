// bench_manager: cost of one manager step (forces + tree ticks + integration, one thread) on a
// crowd of regular people in a square hall with walls, and the error of the social-force cut-off
// against all pairs on random crowds.
//   bench_manager [--agents N] [--hall L] [--steps S] [--cutoff R] [--error] [--no-exact]
#include "hunav/manager/agent_manager.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

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

double timeSteps(int n, double hall, int steps, double cutoff) {
  AgentManager m;
  m.setSocialCutoff(cutoff);
  step_request_t r = crowd(n, hall, 42);
  wallPoints(r, hall);
  m.step(r);  // warm-up: trees built
  double total = 0.0;
  for (int s = 0; s < steps; ++s) {
    r.seq += 1;
    const auto t0 = std::chrono::steady_clock::now();
    step_reply_t rep = m.step(r);
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.agents = std::move(rep.agents);
    r.utime = rep.utime;
    wallPoints(r, hall);
  }
  return total / steps * 1e3;
}

void cutoffError(double cutoff, int crowds, int n, double hall) {
  double sum_err = 0.0, max_err = 0.0, sum_force = 0.0, max_rel = 0.0;
  long count = 0;
  for (int k = 0; k < crowds; ++k) {
    const step_request_t r = crowd(n, hall, 1000 + static_cast<std::uint64_t>(k));
    StepSnapshot exact;
    exact.request = &r;
    for (const auto& a : r.agents) exact.agents.push_back(SfmBody{a.id, -1, Vec2(a.x, a.y), Vec2(a.vx, a.vy), a.radius});
    exact.index();
    StepSnapshot cut = exact;
    NeighborGrid grid;
    grid.build(cut.agents, cut.by_id, cutoff);
    computePeopleSocial(cut, grid, cutoff);
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
  std::printf("cutoff %.1f m: mean |F_soc| %.5f, mean error %.6f (%.3f%% of mean force), max error %.6f, "
              "max relative error %.2f%%\n",
              cutoff, sum_force / count, sum_err / count, 100.0 * sum_err / sum_force, max_err, 100.0 * max_rel);
}

}  // namespace

int main(int argc, char** argv) {
  int n = 1000, steps = 200;
  double hall = 40.0, cutoff = kDefaultSocialCutoff;
  bool error = false, exact = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? argv[++i] : (std::fprintf(stderr, "%s: value missing\n", a.c_str()), std::exit(2), ""); };
    if (a == "--agents") n = std::atoi(next());
    else if (a == "--hall") hall = std::atof(next());
    else if (a == "--steps") steps = std::atoi(next());
    else if (a == "--cutoff") cutoff = std::atof(next());
    else if (a == "--error") error = true;
    else if (a == "--no-exact") exact = false;
    else {
      std::fprintf(stderr, "usage: bench_manager [--agents N] [--hall L] [--steps S] [--cutoff R] [--error] [--no-exact]\n");
      return 2;
    }
  }
  if (error) {
    for (double c : {2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 7.5, 8.0, 10.0}) cutoffError(c, 5, n, hall);
    return 0;
  }
  const double grid_ms = timeSteps(n, hall, steps, cutoff);
  if (!exact) {
    std::printf("%d agents, %.0f x %.0f m hall: %.3f ms/step with cut-off %.1f m\n", n, hall, hall, grid_ms, cutoff);
    return 0;
  }
  const double exact_ms = timeSteps(n, hall, std::max(1, steps / (n >= 5000 ? 20 : 1)), 0.0);
  std::printf("%d agents, %.0f x %.0f m hall: %.3f ms/step with cut-off %.1f m, %.3f ms/step all pairs\n", n, hall,
              hall, grid_ms, cutoff, exact_ms);
  return 0;
}
