#pragma once
// Test helper: the sample an exhaustive search of the dynamic window would pick, to check the
// planners' branch and bound against.
#include <gtest/gtest.h>

#include "dwb_planner.hpp"
#include "hunav/testing/sim_tools.hpp"

namespace hunav::planners {

// Scores every sample of the window as the planner samples it (dwb_planner.cpp: speeds from the
// fastest down, yaw rates from the lowest up), with the planner's own critics and the context of
// its last plan(), and returns the cheapest admissible one (the first of equal cost).
inline bool exhaustiveBest(const DwbPlanner& planner, const robot_observation_t& obs, double& best_v, double& best_w) {
  const DwbParams& p = planner.params();
  const VelocityWindow win = VelocityWindow::fromObservation(obs);
  const int nv = win.v_max - win.v_min > 1e-9 ? p.v_samples : 1;
  const int nw = win.w_max - win.w_min > 1e-9 ? p.w_samples : 1;
  const double dv = nv > 1 ? (win.v_max - win.v_min) / (nv - 1) : 0.0;
  const double dw = nw > 1 ? (win.w_max - win.w_min) / (nw - 1) : 0.0;
  const PlanningContext& ctx = planner.context();
  double best = TrajectoryCritic::kReject;
  Trajectory t;
  for (int iv = 0; iv < nv; ++iv)
    for (int iw = 0; iw < nw; ++iw) {
      const double v = win.v_max - iv * dv, w = win.w_min + iw * dw;
      rollout(ctx.robot, ctx.robot_yaw, v, w, p.sim_time, p.sim_step, t);
      double total = 0.0;
      for (const auto& critic : planner.critics()) {
        const double score = critic->score(t, ctx);
        total = score == TrajectoryCritic::kReject ? score : total + critic->weight() * score;
        if (total == TrajectoryCritic::kReject) break;
      }
      if (total < best) {
        best = total;
        best_v = v;
        best_w = w;
      }
    }
  return best < TrajectoryCritic::kReject;
}

// How many of a run's sampled decisions were checked, and how many of those had people in view.
struct ExhaustiveComparison {
  int compared = 0;
  int with_people = 0;
};

// Drives `world` with `planner` (a plan every 10 steps of 0.01 s, up to 40 s or the goal) and checks
// every sampled decision against exhaustiveBest: branch and bound must pick exactly the same sample.
inline void compareWithExhaustiveSearch(DwbPlanner& planner, hunav::testing::MiniWorld& world,
                                        ExhaustiveComparison& out) {
  robot_command_t cmd{};
  for (int tick = 0; world.time() < 40.0; ++tick) {
    if (tick % 10 == 0) {
      const robot_observation_t obs = world.observe();
      cmd = planner.plan(obs);
      if (planner.lastDecision() == DwbPlanner::Decision::AtGoal) return;
      if (planner.lastDecision() == DwbPlanner::Decision::Sampled) {
        double v = 0.0, w = 0.0;
        ASSERT_TRUE(exhaustiveBest(planner, obs, v, w));
        EXPECT_EQ(cmd.v, v) << "t " << world.time();
        EXPECT_EQ(cmd.w, w) << "t " << world.time();
        ++out.compared;
        out.with_people += !planner.context().people.empty();
      }
    }
    world.step(cmd.v, cmd.w, 0.01);
  }
}

}  // namespace hunav::planners
