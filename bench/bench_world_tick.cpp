// One world tick with a crowd: 1000 people walking in a 40 x 40 m hall with walls and pillars.
// A tick is what the world does every dt besides messaging: set the people's velocities, step Box2D,
// the obstacle points within 3 m and the line of sight to the robot for every person, and one laser
// scan of 360 beams. Target: <= 1.5 ms per tick.
//
// Measured as CPU time of this thread (CLOCK_THREAD_CPUTIME_ID) per tick, so other processes on the
// machine do not inflate it; the minimum and the median over many ticks are the figures to report.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <vector>

#include "physics_world.hpp"
#include "sensors.hpp"

using namespace hunav;
using hunav::worldsim::PhysicsWorld;

namespace {

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

Shape polyline(std::vector<Vec2> points) {
  Shape s;
  s.kind = Shape::Kind::Polyline;
  s.points = std::move(points);
  return s;
}

Shape box(const Vec2& c, double half) {
  Shape s;
  s.kind = Shape::Kind::Polygon;
  s.points = {c + Vec2(-half, -half), c + Vec2(half, -half), c + Vec2(half, half), c + Vec2(-half, half)};
  return s;
}

// The hall: outer walls, two partial inner walls, a 5 x 5 grid of 0.8 m pillars; the robot in the
// middle; people on a grid wherever they are clear of every shape.
Scenario hall(int people) {
  Scenario s;
  s.name = "bench_hall";
  s.shapes.push_back(polyline({Vec2(0, 0), Vec2(40, 0), Vec2(40, 40), Vec2(0, 40), Vec2(0, 0)}));
  s.shapes.push_back(polyline({Vec2(10, 13), Vec2(18, 13)}));
  s.shapes.push_back(polyline({Vec2(22, 27), Vec2(30, 27), Vec2(30, 33)}));
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) s.shapes.push_back(box(Vec2(4.0 + 8.0 * i, 4.0 + 8.0 * j), 0.4));
  s.robot.radius = 0.3;
  s.robot.start = Vec2(16.0, 16.0);  // between the pillars
  s.robot.laser.beams = 360;
  s.robot.laser.fov = 2.0 * kPi;
  s.robot.laser.range_max = 8.0;
  const double spacing = 1.15;
  for (double y = 0.8; y < 40.0 - 0.8 && static_cast<int>(s.agents.size()) < people; y += spacing) {
    for (double x = 0.8; x < 40.0 - 0.8 && static_cast<int>(s.agents.size()) < people; x += spacing) {
      const Vec2 p(x, y);
      if ((p - s.robot.start).norm() < 1.0) continue;
      bool clear = true;
      for (const Shape& sh : s.shapes) clear = clear && sh.distance(p) > 0.45;
      if (!clear) continue;
      AgentConfig a;
      a.id = static_cast<int>(s.agents.size()) + 1;
      a.position = p;
      a.radius = 0.3;
      s.agents.push_back(a);
    }
  }
  return s;
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5));
  return v[i];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_world_tick: CPU time of one world tick with a crowd in a 40 x 40 m hall"};
  int people = 1000, ticks = 2000, warmup = 200;
  app.add_option("--people", people, "people in the hall")->check(CLI::Range(1, 1100));
  app.add_option("--ticks", ticks, "measured ticks")->check(CLI::PositiveNumber);
  app.add_option("--warmup", warmup, "ticks before measuring")->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);

  const Scenario scenario = hall(people);
  if (static_cast<int>(scenario.agents.size()) != people) {
    std::fprintf(stderr, "only %zu people fit in the hall\n", scenario.agents.size());
    return 1;
  }
  PhysicsWorld world(scenario);
  const double dt = 0.01, obstacle_radius = 3.0;
  std::mt19937_64 rng(7), laser_rng(8);
  std::uniform_real_distribution<double> turn(-0.05, 0.05);
  std::vector<double> heading(scenario.agents.size());
  for (double& h : heading) h = std::uniform_real_distribution<double>(-kPi, kPi)(rng);
  std::vector<Vec2> obstacles, positions(scenario.agents.size());
  std::vector<char> in_sight;
  std::vector<double> ranges;
  laser_scan_t scan;

  struct Parts {
    double step = 0, obstacles = 0, sight = 0, laser = 0;
  } total;
  std::vector<double> tick_times;
  std::size_t obstacle_points = 0, visible = 0, contacts = 0;
  for (int t = 0; t < warmup + ticks; ++t) {
    // People wander at 1.2 m/s with a slowly turning heading; Box2D resolves their contacts.
    for (std::size_t i = 0; i < heading.size(); ++i) heading[i] += turn(rng);
    const double t0 = threadCpuSeconds();
    for (std::size_t i = 0; i < heading.size(); ++i)
      world.person(i).SetLinearVelocity(
          b2Vec2(static_cast<float>(1.2 * std::cos(heading[i])), static_cast<float>(1.2 * std::sin(heading[i]))));
    world.step(dt);
    const double t1 = threadCpuSeconds();
    const Vec2 robot = worldsim::toVec(world.robot().GetPosition());
    std::size_t points = 0;
    for (std::size_t i = 0; i < world.personCount(); ++i) {
      world.closestObstaclePoints(worldsim::toVec(world.person(i).GetPosition()), obstacle_radius, obstacles);
      points += obstacles.size();
    }
    const double t2 = threadCpuSeconds();
    for (std::size_t i = 0; i < world.personCount(); ++i) positions[i] = worldsim::toVec(world.person(i).GetPosition());
    world.linesOfSightTo(robot, positions, in_sight);
    std::size_t seen = 0;
    for (const char v : in_sight) seen += v ? 1 : 0;
    const double t3 = threadCpuSeconds();
    worldsim::laserScan(world, robot, world.robot().GetAngle(), scenario.robot.laser, laser_rng, scan, ranges);
    const double t4 = threadCpuSeconds();
    if (t < warmup) continue;
    total.step += t1 - t0;
    total.obstacles += t2 - t1;
    total.sight += t3 - t2;
    total.laser += t4 - t3;
    tick_times.push_back(t4 - t0);
    obstacle_points += points;
    visible += seen;
    contacts += world.newContacts().size();
  }

  const double n = static_cast<double>(ticks);
  std::printf("world tick, %d people in a 40 x 40 m hall (%zu static shapes), %d ticks after %d warm-up ticks\n",
              people, scenario.shapes.size(), ticks, warmup);
  std::printf(
      "  per tick (thread CPU time): min %.3f ms, median %.3f ms, p90 %.3f ms, mean %.3f ms  (target <= 1.5 ms)\n",
      1e3 * percentile(tick_times, 0.0), 1e3 * percentile(tick_times, 0.5), 1e3 * percentile(tick_times, 0.9),
      1e3 * (total.step + total.obstacles + total.sight + total.laser) / n);
  std::printf(
      "  mean parts: box2d step (with velocities) %.3f ms, obstacle points %.3f ms, line of sight %.3f ms, "
      "laser 360 beams %.3f ms\n",
      1e3 * total.step / n, 1e3 * total.obstacles / n, 1e3 * total.sight / n, 1e3 * total.laser / n);
  std::printf("  per tick: %.1f obstacle points, %.1f people in sight of the robot, %.2f new contacts\n",
              static_cast<double>(obstacle_points) / n, static_cast<double>(visible) / n,
              static_cast<double>(contacts) / n);
  return 0;
}
