#include "sample_view.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hunav/evaluator/metrics.hpp"
#include "metrics_internal.hpp"

namespace hunav::evaluator {

namespace {
enum : std::uint32_t {
  kSurface = 1u << 0,
  kSocialOnPerson = 1u << 1,
  kSocialOnRobot = 1u << 2,
  kV1OnPerson = 1u << 3,
  kV1OnRobot = 1u << 4,
  kObstacle = 1u << 5,
  kAhead = 1u << 6,
  kFear = 1u << 7,
  kPanic = 1u << 8,
  kVisible = 1u << 9,
};

Vec2 velocityOf(const EntityState& e) { return Vec2(e.vx, e.vy); }
}  // namespace

double SampleView::surfaceDistance(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kSurface)) {
    const EntityState& a = agent(j);
    p.surface = (robot().position() - a.position()).norm() - robot().radius - a.radius;
    p.have |= kSurface;
  }
  return p.surface;
}

const Vec2& SampleView::socialForceOnPerson(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kSocialOnPerson)) {
    p.social_on_person = socialForceFrom(sfmBody(agent(j)), sfmBody(robot()), modelSfmParams());
    p.have |= kSocialOnPerson;
  }
  return p.social_on_person;
}

const Vec2& SampleView::socialForceOnRobot(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kSocialOnRobot)) {
    p.social_on_robot = socialForceFrom(sfmBody(robot()), sfmBody(agent(j)), modelSfmParams());
    p.have |= kSocialOnRobot;
  }
  return p.social_on_robot;
}

const Vec2& SampleView::v1ForceOnPerson(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kV1OnPerson)) {
    const EntityState& a = agent(j);
    p.v1_on_person = metrics_v1::socialForceV1(a.position(), velocityOf(a), robot().position(), velocityOf(robot()));
    p.have |= kV1OnPerson;
  }
  return p.v1_on_person;
}

const Vec2& SampleView::v1ForceOnRobot(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kV1OnRobot)) {
    const EntityState& a = agent(j);
    p.v1_on_robot = metrics_v1::socialForceV1(robot().position(), velocityOf(robot()), a.position(), velocityOf(a));
    p.have |= kV1OnRobot;
  }
  return p.v1_on_robot;
}

const Vec2& SampleView::obstacleForceSum(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kObstacle)) {
    const EntityState& a = agent(j);
    p.obstacle = obstacleForceOf(sfmBody(a), obstacles(a), modelSfmParams(), false);
    p.have |= kObstacle;
  }
  return p.obstacle;
}

const Vec2& SampleView::robotObstacleForceSum() const {
  if (!cache_->have_robot_obstacle_) {
    cache_->robot_obstacle_ = obstacleForceOf(sfmBody(robot()), obstacles(robot()), modelSfmParams(), false);
    cache_->have_robot_obstacle_ = true;
  }
  return cache_->robot_obstacle_;
}

const Vec2& SampleView::aheadPoint(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kAhead)) {
    const EntityState& a = agent(j);
    p.ahead = Vec2(a.x + kGroupCentreAhead * std::cos(a.yaw), a.y + kGroupCentreAhead * std::sin(a.yaw));
    p.have |= kAhead;
  }
  return p.ahead;
}

double SampleView::fear(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kFear)) {
    p.fear = dangerFearAt(robot(), agent(j));
    p.have |= kFear;
  }
  return p.fear;
}

double SampleView::panic(std::size_t j) const {
  auto& p = person(j);
  if (!(p.have & kPanic)) {
    p.panic = dangerPanicAt(robot(), agent(j));
    p.have |= kPanic;
  }
  return p.panic;
}

bool SampleView::visible(std::size_t j, double& theta, double& distance) const {
  auto& p = person(j);
  if (!(p.have & kVisible)) {
    p.theta = 0.0;
    p.distance = 0.0;
    p.visible = visibleAngle(robot(), agent(j), p.theta, p.distance);
    p.have |= kVisible;
  }
  theta = p.theta;
  distance = p.distance;
  return p.visible;
}

bool SampleView::closestPerson(std::size_t& j) const {
  if (size_ == 0) return false;
  if (!have_closest_) {
    std::size_t best = 0;
    double best_d = surfaceDistance(0);
    for (std::size_t i = 1; i < size_; ++i) {
      const double d = surfaceDistance(i);
      if (d < best_d) {
        best_d = d;
        best = i;
      }
    }
    closest_ = best;
    have_closest_ = true;
  }
  j = closest_;
  return true;
}

double SampleView::closestPersonDistance() const {
  std::size_t j = 0;
  closestPerson(j);
  return std::max(0.0, surfaceDistance(j));
}

bool SampleView::closestGroupDistance(double& g) const {
  if (!have_group_) {
    // Groups in the order of their first member in the view; each centre sums its members in view
    // order.
    double best = std::numeric_limits<double>::max();
    bool any = false;
    for (std::size_t i = 0; i < size_; ++i) {
      const std::int32_t id = agent(i).group;
      if (id == -1) continue;
      bool seen_before = false;
      for (std::size_t k = 0; k < i && !seen_before; ++k) seen_before = agent(k).group == id;
      if (seen_before) continue;
      Vec2 sum = Vec2::Zero();
      int members = 0;
      for (std::size_t k = i; k < size_; ++k) {
        if (agent(k).group != id) continue;
        sum += aheadPoint(k);
        ++members;
      }
      const Vec2 centre = sum / static_cast<double>(members);
      best = std::min(best, std::max(0.0, (robot().position() - centre).norm() - robot().radius));
      any = true;
    }
    group_present_ = any;
    group_distance_ = best;
    have_group_ = true;
  }
  if (group_present_) g = group_distance_;
  return group_present_;
}

}  // namespace hunav::evaluator
