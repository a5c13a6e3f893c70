#include "hunav/testing/sim_tools.hpp"

#include <algorithm>
#include <cmath>

#include "trajectory.hpp"

namespace hunav::testing {

namespace {
double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Ray parameter t >= 0 where origin + t*dir crosses segment ab, or max when it does not.
double raySegment(const Vec2& origin, const Vec2& dir, const Vec2& a, const Vec2& b, double max) {
  const Vec2 ab = b - a;
  const double denom = cross(dir, ab);
  if (std::abs(denom) < 1e-12) return max;  // parallel
  const Vec2 ao = a - origin;
  const double t = cross(ao, ab) / denom;
  const double u = cross(ao, dir) / denom;
  return t >= 0.0 && u >= 0.0 && u <= 1.0 ? std::min(t, max) : max;
}

double rayCircle(const Vec2& origin, const Vec2& dir, const Vec2& center, double radius, double max) {
  const Vec2 oc = origin - center;
  const double b = oc.dot(dir);
  const double c = oc.squaredNorm() - radius * radius;
  if (c <= 0.0) return 0.0;  // the origin is inside
  const double disc = b * b - c;
  if (disc < 0.0) return max;
  const double t = -b - std::sqrt(disc);
  return t >= 0.0 ? std::min(t, max) : max;
}
}  // namespace

double castRay(const std::vector<Shape>& shapes, const std::vector<Circle>& bodies, const Vec2& origin, double angle,
               double max_range) {
  const Vec2 dir(std::cos(angle), std::sin(angle));
  double range = max_range;
  for (const Shape& shape : shapes) {
    if (shape.kind == Shape::Kind::Circle) {
      range = rayCircle(origin, dir, shape.center, shape.radius, range);
      continue;
    }
    const std::size_t n = shape.points.size();
    const std::size_t edges = shape.kind == Shape::Kind::Polygon ? n : n - 1;
    for (std::size_t i = 0; i < edges; ++i)
      range = raySegment(origin, dir, shape.points[i], shape.points[(i + 1) % n], range);
  }
  for (const Circle& body : bodies) range = rayCircle(origin, dir, body.center, body.radius, range);
  return range;
}

laser_scan_t simulateScan(const std::vector<Shape>& shapes, const std::vector<Circle>& bodies, const Vec2& position,
                          double yaw, const LaserConfig& laser, std::int64_t utime) {
  laser_scan_t scan;
  scan.utime = utime;
  scan.sensor_x = position.x();
  scan.sensor_y = position.y();
  scan.sensor_yaw = yaw;
  // A full circle has no duplicate beam at +pi; a partial fan covers both of its edges.
  const bool full_circle = laser.fov >= 2.0 * kPi - 1e-9;
  scan.angle_min = -laser.fov / 2.0;
  scan.angle_increment = full_circle || laser.beams < 2 ? laser.fov / laser.beams : laser.fov / (laser.beams - 1);
  scan.range_min = laser.range_min;
  scan.range_max = laser.range_max;
  scan.num_ranges = laser.beams;
  scan.ranges.resize(static_cast<std::size_t>(laser.beams));
  for (int i = 0; i < laser.beams; ++i) {
    const double angle = yaw + scan.angle_min + i * scan.angle_increment;
    const double r = castRay(shapes, bodies, position, angle, laser.range_max);
    scan.ranges[static_cast<std::size_t>(i)] = static_cast<float>(std::max(r, laser.range_min));
  }
  return scan;
}

robot_observation_t makeObservation(const Scenario& scenario, const Vec2& position, double yaw, double v, double w,
                                    std::int64_t utime, std::int64_t seq, std::int64_t episode) {
  const RobotConfig& robot = scenario.robot;
  robot_observation_t obs;
  obs.utime = utime;
  obs.seq = seq;
  obs.episode = episode;
  obs.x = position.x();
  obs.y = position.y();
  obs.yaw = yaw;
  obs.v = v;
  obs.w = w;
  obs.radius = robot.radius;
  obs.max_v = robot.limits.max_v;
  obs.min_v = robot.limits.min_v;
  obs.max_w = robot.limits.max_w;
  obs.max_acc_v = robot.limits.max_acc_v;
  obs.max_acc_w = robot.limits.max_acc_w;
  obs.control_period = 1.0 / robot.control_rate;
  obs.goal.utime = 0;
  obs.goal.valid = robot.has_goal;
  obs.goal.x = robot.goal.x();
  obs.goal.y = robot.goal.y();
  obs.goal.yaw = robot.goal_yaw;
  obs.goal.radius = robot.goal_radius;
  obs.scan = laser_scan_t();
  obs.scan.utime = utime;
  obs.scan.sensor_x = position.x();
  obs.scan.sensor_y = position.y();
  obs.scan.sensor_yaw = yaw;
  obs.scan.angle_min = obs.scan.angle_increment = obs.scan.range_min = obs.scan.range_max = 0.0;
  obs.scan.num_ranges = 0;
  obs.num_people = 0;
  return obs;
}

MiniWorld::MiniWorld(const Scenario& scenario)
    : scenario_(scenario), robot_(scenario.robot.start), yaw_(scenario.robot.start_yaw) {
  for (const AgentConfig& agent : scenario.agents) {
    Person p;
    p.id = agent.id;
    p.position = agent.position;
    p.radius = agent.radius;
    people_.push_back(p);
    person_goals_.push_back(agent.goals.empty() ? std::vector<Vec2>{agent.position} : agent.goals);
    person_next_.push_back(0);
    person_cyclic_.push_back(agent.cyclic_goals);
    person_speed_.push_back(agent.goals.empty() ? 0.0 : agent.max_vel);
    person_goal_radius_.push_back(agent.goal_radius);
  }
}

robot_observation_t MiniWorld::observe() {
  const auto utime = static_cast<std::int64_t>(std::llround(time_ * 1e6));
  robot_observation_t obs = makeObservation(scenario_, robot_, yaw_, v_, w_, utime, ++seq_, 1);
  std::vector<Circle> bodies;
  for (const Person& p : people_) bodies.push_back({p.position, p.radius});
  obs.scan = simulateScan(scenario_.shapes, bodies, robot_, yaw_, scenario_.robot.laser, utime);
  for (const Person& p : people_) {
    if ((p.position - robot_).norm() > scenario_.robot.perception_range) continue;
    detected_person_t d;
    d.id = p.id;
    d.x = p.position.x();
    d.y = p.position.y();
    d.yaw = p.velocity.squaredNorm() > 0.0 ? angleOf(p.velocity) : 0.0;
    d.vx = p.velocity.x();
    d.vy = p.velocity.y();
    d.radius = p.radius;
    obs.people.push_back(d);
  }
  obs.num_people = static_cast<std::int32_t>(obs.people.size());
  return obs;
}

void MiniWorld::step(double v, double w, double dt) {
  planners::stepUnicycle(robot_, yaw_, v, w, dt);
  v_ = v;
  w_ = w;
  for (std::size_t i = 0; i < people_.size(); ++i) {
    Person& p = people_[i];
    const std::vector<Vec2>& goals = person_goals_[i];
    std::size_t& next = person_next_[i];
    // At a goal (within its radius, or a step of it), on to the next one: after the last, the first
    // again (cyclic) or stay.
    const double reached = std::max(person_goal_radius_[i], person_speed_[i] * dt);
    if ((goals[next] - p.position).norm() <= reached && (next + 1 < goals.size() || person_cyclic_[i]))
      next = (next + 1) % goals.size();
    const Vec2 to_goal = goals[next] - p.position;
    p.velocity = to_goal.norm() > person_goal_radius_[i] ? Vec2(normalizedOrZero(to_goal) * person_speed_[i])
                                                         : Vec2(Vec2::Zero());
    p.position += p.velocity * dt;
  }
  time_ += dt;
}

}  // namespace hunav::testing
