#include "hunav/orca.hpp"

#include <algorithm>
#include <cmath>

namespace hunav {

namespace {

// Below this a length or a violation counts as zero (m/s; people move at ~1 m/s).
constexpr double kEps = 1e-9;

Vec2 rightNormal(const Vec2& v) { return Vec2(v.y(), -v.x()); }
double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// What the velocity is chosen for: as close as possible to a target velocity, or as far as possible
// along a unit direction (the fallback's "exceed this plane least").
enum class Objective { Closest, Farthest };

// The best point of the boundary line of planes[i] that lies in the disc and in planes[0, i).
// False when there is none.
bool bestOnLine(const std::vector<HalfPlane>& planes, std::size_t i, double max_speed, const Vec2& target,
                Objective objective, Vec2& result) {
  const HalfPlane& line = planes[i];
  const Vec2 d = rightNormal(line.normal);  // along the line
  // |point + t d|^2 <= R^2: t^2 + 2 b t + |point|^2 - R^2 <= 0.
  const double b = line.point.dot(d);
  const double disc = b * b - (line.point.squaredNorm() - max_speed * max_speed);
  if (disc < 0.0) return false;
  double lo = -b - std::sqrt(disc), hi = -b + std::sqrt(disc);
  for (std::size_t j = 0; j < i; ++j) {
    // n_j . (point + t d - point_j) >= 0  <=>  t (n_j . d) >= n_j . (point_j - point)
    const double den = planes[j].normal.dot(d);
    const double num = planes[j].normal.dot(planes[j].point - line.point);
    if (std::abs(den) < kEps) {
      if (num > kEps) return false;  // parallel and wholly outside plane j
      continue;
    }
    const double t = num / den;
    if (den > 0.0)
      lo = std::max(lo, t);
    else
      hi = std::min(hi, t);
    if (lo > hi) return false;
  }
  double t;
  if (objective == Objective::Closest)
    t = std::clamp((target - line.point).dot(d), lo, hi);
  else if (std::abs(target.dot(d)) < kEps)
    t = std::clamp(0.0, lo, hi);  // every point of the line is as good: the one nearest the line's foot
  else
    t = target.dot(d) > 0.0 ? hi : lo;
  result = line.point + t * d;
  return true;
}

// Seidel's incremental linear program over the planes in order: when the best velocity so far
// violates the next plane, the new best lies on that plane's line. Returns planes.size() when every
// plane holds, else the index of the first plane that cannot be met (v: the best for the earlier ones).
std::size_t incremental(const std::vector<HalfPlane>& planes, double max_speed, const Vec2& target, Objective objective,
                        Vec2& v) {
  if (objective == Objective::Farthest)
    v = target * max_speed;
  else
    v = target.norm() > max_speed ? Vec2(target.normalized() * max_speed) : target;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    if (planes[i].violation(v) <= kEps) continue;
    const Vec2 before = v;
    if (!bestOnLine(planes, i, max_speed, target, objective, v)) {
      v = before;
      return i;
    }
  }
  return planes.size();
}

}  // namespace

HalfPlane orcaHalfPlane(const Vec2& position, const Vec2& velocity, double radius, const Vec2& other_position,
                        const Vec2& other_velocity, double other_radius, double tau, double responsibility, double dt) {
  const Vec2 p = other_position - position;  // where the neighbour is, relative to me
  const Vec2 vrel = velocity - other_velocity;
  const double r = radius + other_radius;
  const double dist2 = p.squaredNorm(), r2 = r * r;
  Vec2 n, u;
  if (dist2 > r2) {
    // w: from the cut-off disc's centre p / tau to the relative velocity.
    const Vec2 w = vrel - p / tau;
    const double wp = w.dot(p), w2 = w.squaredNorm();
    if (wp < 0.0 && wp * wp > r2 * w2) {
      // Nearest to the cut-off arc: w points back toward the origin, within the angle of the
      // tangent points (cos = r / |p|).
      const double wl = std::sqrt(w2);
      n = w / wl;
      u = (r / tau - wl) * n;
    } else {
      // Nearest to a leg: the tangent from the origin on w's side of p, at sin = r / |p| from p.
      const double leg = std::sqrt(dist2 - r2);
      if (cross(p, w) > 0.0) {
        const Vec2 dir = Vec2(p.x() * leg - p.y() * r, p.x() * r + p.y() * leg) / dist2;
        n = leftNormal(dir);  // outward: the left leg's outside is further counter-clockwise
      } else {
        const Vec2 dir = Vec2(p.x() * leg + p.y() * r, -p.x() * r + p.y() * leg) / dist2;
        n = rightNormal(dir);
      }
      u = -n.dot(vrel) * n;  // vrel projected on the leg's line, minus vrel
    }
  } else {
    // Overlapping already: the velocity obstacle of one step (centre p / dt, radius r / dt).
    const Vec2 w = vrel - p / dt;
    const double wl = w.norm();
    n = wl > 0.0 ? Vec2(w / wl) : (dist2 > 0.0 ? Vec2(-p.normalized()) : Vec2(Vec2::UnitX()));
    u = (r / dt - wl) * n;
  }
  return HalfPlane{velocity + responsibility * u, n};
}

HalfPlane obstacleHalfPlane(const Vec2& position, double radius, const Vec2& closest, double tau) {
  const Vec2 away = position - closest;
  const double d = away.norm();
  if (!(d > 0.0)) return HalfPlane{Vec2(-1e12, 0.0), Vec2::UnitX()};  // no direction: no constraint
  const Vec2 n = away / d;
  const double allowed = d > radius ? (d - radius) / tau : 0.0;  // approach speed toward the obstacle
  return HalfPlane{-allowed * n, n};
}

Vec2 solveOrcaVelocity(const std::vector<HalfPlane>& planes, std::size_t hard, const Vec2& preferred,
                       double max_speed) {
  max_speed = std::max(max_speed, 0.0);
  Vec2 v;
  const std::size_t failed = incremental(planes, max_speed, preferred, Objective::Closest, v);
  if (failed == planes.size()) return v;
  // Not every plane can hold. The obstacle planes (the first `hard`, as many as hold together) stay
  // hard; among the people's planes take the velocity whose largest violation is smallest: plane by
  // plane, when plane i is violated more than the worst so far, the best velocity makes it the worst
  // one, so it maximises n_i . v subject to the obstacles and to "plane j violated no more than plane
  // i" for the earlier people's planes j, a half-plane (n_j - n_i) . v >= n_j . p_j - n_i . p_i.
  const std::size_t kept = std::min(hard, failed);
  double worst = 0.0;
  std::vector<HalfPlane> sub;
  for (std::size_t i = std::max(failed, kept); i < planes.size(); ++i) {
    if (planes[i].violation(v) <= worst + kEps) continue;
    sub.assign(planes.begin(), planes.begin() + static_cast<std::ptrdiff_t>(kept));
    for (std::size_t j = kept; j < i; ++j) {
      const Vec2 m = planes[j].normal - planes[i].normal;
      const double ml2 = m.squaredNorm();
      if (ml2 < kEps * kEps) continue;  // parallel, same side: their violations differ by a constant
      const double rhs = planes[j].normal.dot(planes[j].point) - planes[i].normal.dot(planes[i].point);
      sub.push_back(HalfPlane{m * (rhs / ml2), m / std::sqrt(ml2)});
    }
    const Vec2 before = v;
    if (incremental(sub, max_speed, planes[i].normal, Objective::Farthest, v) < sub.size()) v = before;  // rounding
    worst = planes[i].violation(v);
  }
  return v;
}

}  // namespace hunav
