// The stuck rule alone (scenario keys stuck_timeout, stuck_distance): positions fed tick by tick,
// with exact times; test_world_sim.cpp runs it inside the world.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>

#include "stuck_detector.hpp"

using hunav::Vec2;
using hunav::worldsim::StuckDetector;

namespace {

constexpr std::int64_t kTick = 10000;  // us: dt = 0.01 s
constexpr std::int64_t kSecond = 1000000;

// Feeds position(t) every tick from t = 0 up to `until_us`; the first time (us) update() said stuck.
std::optional<std::int64_t> firstStuck(StuckDetector& d, std::int64_t until_us,
                                       const std::function<Vec2(double)>& position) {
  for (std::int64_t t = 0; t <= until_us; t += kTick)
    if (d.update(t, position(static_cast<double>(t) / 1e6))) return t;
  return std::nullopt;
}

}  // namespace

TEST(StuckDetector, StandingStillIsStuckExactlyAtTheTimeout) {
  // Anchor at t = 0; nothing moves: stuck on the tick where t - 0 >= 5 s, t = 5.00 s (tick 500).
  StuckDetector d(5 * kSecond, 0.5, Vec2(4.0, 2.0));
  EXPECT_EQ(firstStuck(d, 20 * kSecond, [](double) { return Vec2(1.0, 2.0); }), 5 * kSecond);
  EXPECT_EQ(d.reason(),
            "the robot made no progress for 5 s (stayed within 0.5 m of (1.00, 2.00), best distance to goal 3.00 m)");
}

TEST(StuckDetector, ProgressRestartsTheTimer) {
  // Still until 4 s, then 0.6 m away (out of the 0.5 m circle): the anchor moves there at t = 4 s,
  // so stuck at 4 + 5 = 9 s, not 5 s.
  StuckDetector d(5 * kSecond, 0.5, Vec2(10.0, 0.0));
  const auto jump = [](double t) { return t < 4.0 ? Vec2(0.0, 0.0) : Vec2(0.6, 0.0); };
  EXPECT_EQ(firstStuck(d, 20 * kSecond, jump), 9 * kSecond);
  EXPECT_EQ(d.anchor(), Vec2(0.6, 0.0));
  EXPECT_EQ(d.anchorTime(), 4 * kSecond);
}

TEST(StuckDetector, OscillatingWithinTheCircleIsStuck) {
  // x = 0.45 sin(2 pi t): 0.9 m of travel a second, but never 0.5 m from the start (the anchor) nor
  // 0.5 m closer to the goal: stuck at 5 s like a robot standing still.
  StuckDetector d(5 * kSecond, 0.5, Vec2(10.0, 0.0));
  const auto swing = [](double t) { return Vec2(0.45 * std::sin(2.0 * 3.14159265358979 * t), 0.0); };
  EXPECT_EQ(firstStuck(d, 20 * kSecond, swing), 5 * kSecond);
  EXPECT_EQ(d.anchorTime(), 0);
}

TEST(StuckDetector, SteadyMotionIsNeverStuck) {
  // 0.2 m/s toward the goal: out of each 0.5 m circle after 2.5 s (2.51 s: leaving is strict), well
  // within the 5 s timeout, for 100 s.
  StuckDetector d(5 * kSecond, 0.5, Vec2(30.0, 0.0));
  EXPECT_EQ(firstStuck(d, 100 * kSecond, [](double t) { return Vec2(0.2 * t, 0.0); }), std::nullopt);
  EXPECT_GT(d.anchorTime(), 95 * kSecond);
}

TEST(StuckDetector, ComingStuckDistanceCloserToTheGoalIsProgressEvenOnTheCircle) {
  // Exactly 0.5 m from the anchor is still within the circle (leaving is strict); straight toward
  // the goal that is 0.5 m closer than the best distance (10 -> 9.5), which is progress; sideways it is not.
  StuckDetector toward(5 * kSecond, 0.5, Vec2(10.0, 0.0));
  const auto at_half = [](double t) { return t < 1.0 ? Vec2(0.0, 0.0) : Vec2(0.5, 0.0); };
  EXPECT_EQ(firstStuck(toward, 20 * kSecond, at_half), 6 * kSecond);
  StuckDetector sideways(5 * kSecond, 0.5, Vec2(10.0, 0.0));
  const auto aside = [](double t) { return t < 1.0 ? Vec2(0.0, 0.0) : Vec2(0.0, 0.5); };
  EXPECT_EQ(firstStuck(sideways, 20 * kSecond, aside), 5 * kSecond);
}

TEST(StuckDetector, ZeroTimeoutIsNeverStuck) {
  StuckDetector off(0, 0.5, Vec2(10.0, 0.0));
  EXPECT_FALSE(off.enabled());
  EXPECT_EQ(firstStuck(off, 100 * kSecond, [](double) { return Vec2(0.0, 0.0); }), std::nullopt);
  StuckDetector never;
  EXPECT_FALSE(never.update(100 * kSecond, Vec2(0.0, 0.0)));
}

TEST(StuckDetector, ATimeoutBetweenTicksEndsOnTheNextTick) {
  // 2.505 s with 10 ms ticks: t = 2.50 is short of it, t = 2.51 the first tick past it.
  StuckDetector d(2505000, 0.5, Vec2(10.0, 0.0));
  EXPECT_EQ(firstStuck(d, 10 * kSecond, [](double) { return Vec2(0.0, 0.0); }), 2510000);
  EXPECT_EQ(d.reason().rfind("the robot made no progress for 2.51 s (", 0), 0u) << d.reason();
}
