#include "hunav/planners/costmap.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hunav::planners {

Costmap::Costmap(const Scenario& scenario, double robot_radius, const CostmapParams& params)
    : params_(params), shapes_(scenario.shapes), robot_radius_(robot_radius) {
  Vec2 lo, hi;
  scenario.bounds(lo, hi, params.margin);
  origin_ = lo;
  width_ = static_cast<int>(std::ceil((hi.x() - lo.x()) / params_.resolution));
  height_ = static_cast<int>(std::ceil((hi.y() - lo.y()) / params_.resolution));
  buildStaticLayer();
}

Costmap::Costmap(std::vector<Shape> shapes, const Vec2& lo, const Vec2& hi, double robot_radius,
                 const CostmapParams& params)
    : params_(params), shapes_(std::move(shapes)), robot_radius_(robot_radius), origin_(lo) {
  width_ = static_cast<int>(std::ceil((hi.x() - lo.x()) / params_.resolution));
  height_ = static_cast<int>(std::ceil((hi.y() - lo.y()) / params_.resolution));
  buildStaticLayer();
}

bool Costmap::worldToCell(const Vec2& p, int& cx, int& cy) const {
  const double fx = std::floor((p.x() - origin_.x()) / params_.resolution);
  const double fy = std::floor((p.y() - origin_.y()) / params_.resolution);
  // Clamp in double first: a far-away (or huge) coordinate must not overflow the int conversion.
  cx = static_cast<int>(std::clamp(fx, -1.0, static_cast<double>(width_)));
  cy = static_cast<int>(std::clamp(fy, -1.0, static_cast<double>(height_)));
  const bool inside = inBounds(cx, cy);
  cx = std::clamp(cx, 0, width_ - 1);
  cy = std::clamp(cy, 0, height_ - 1);
  return inside;
}

Vec2 Costmap::cellCenter(int cx, int cy) const {
  return origin_ + Vec2((cx + 0.5) * params_.resolution, (cy + 0.5) * params_.resolution);
}

std::uint8_t Costmap::costFromDistance(double distance) const {
  if (distance <= lethal_distance_) return kLethal;
  if (distance <= robot_radius_) return kInscribed;
  if (distance >= inflation_) return kFree;
  const double beyond = distance - robot_radius_;
  const auto step = static_cast<std::size_t>(beyond / decay_step_);
  return step < decay_.size() ? decay_[step] : kFree;
}

void Costmap::setRobotRadius(double robot_radius) {
  if (robot_radius == robot_radius_) return;
  robot_radius_ = robot_radius;
  buildStaticLayer();
}

void Costmap::buildStaticLayer() {
  const double res = params_.resolution;
  if (!(res > 0.0) || width_ <= 0 || height_ <= 0) throw std::invalid_argument("costmap: empty grid");
  if (!(robot_radius_ > 0.0)) throw std::invalid_argument("costmap: robot radius must be > 0");
  lethal_distance_ = 0.5 * std::sqrt(2.0) * res * (1.0 + 1e-9);  // a point on a cell corner is in it
  // The decaying cost must reach at least one cell past the robot radius.
  inflation_ = std::max(params_.inflation_radius, robot_radius_ + res);

  // Cost beyond the robot radius (nav2's inflation formula), tabulated every 1/8 cell.
  decay_step_ = res / 8.0;
  const auto decay_steps = static_cast<std::size_t>(std::ceil((inflation_ - robot_radius_) / decay_step_));
  decay_.resize(decay_steps);
  for (std::size_t k = 0; k < decay_steps; ++k) {
    const double c = kMaxInflated * std::exp(-params_.cost_scaling_factor * static_cast<double>(k) * decay_step_);
    decay_[k] = static_cast<std::uint8_t>(std::clamp(c, 1.0, static_cast<double>(kMaxInflated)));
  }

  const std::size_t cells = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  static_distance_.assign(cells, static_cast<float>(inflation_));
  for (const Shape& shape : shapes_) {
    Vec2 lo, hi;
    shape.bounds(lo, hi);
    int x0, y0, x1, y1;
    worldToCell(lo - Vec2(inflation_, inflation_), x0, y0);
    worldToCell(hi + Vec2(inflation_, inflation_), x1, y1);
    for (int cy = y0; cy <= y1; ++cy)
      for (int cx = x0; cx <= x1; ++cx) {
        float& d = static_distance_[static_cast<std::size_t>(index(cx, cy))];
        d = std::min(d, static_cast<float>(shape.distance(cellCenter(cx, cy))));
      }
  }
  static_.resize(cells);
  for (std::size_t i = 0; i < cells; ++i) static_[i] = costFromDistance(static_distance_[i]);
  transient_.assign(cells, kFree);
  touched_.clear();
}

void Costmap::clearTransient() {
  for (int i : touched_) transient_[static_cast<std::size_t>(i)] = kFree;
  touched_.clear();
}

void Costmap::raiseTransientIndex(int i, std::uint8_t cost) {
  std::uint8_t& cell = transient_[static_cast<std::size_t>(i)];
  if (cost <= cell) return;
  if (cell == kFree) touched_.push_back(i);
  cell = cost;
}

void Costmap::raiseTransient(int cx, int cy, std::uint8_t cost) {
  if (inBounds(cx, cy)) raiseTransientIndex(index(cx, cy), cost);
}

void Costmap::markCircle(const Vec2& center, double radius, std::uint8_t max_cost) {
  markCapsule(center, center, radius, max_cost);
}

void Costmap::markCapsule(const Vec2& a, const Vec2& b, double radius, std::uint8_t max_cost) {
  const double reach = radius + inflation_;
  int x0, y0, x1, y1;
  worldToCell(a.cwiseMin(b) - Vec2(reach, reach), x0, y0);
  worldToCell(a.cwiseMax(b) + Vec2(reach, reach), x1, y1);
  const Vec2 ab = b - a;
  const double length2 = ab.squaredNorm();
  for (int cy = y0; cy <= y1; ++cy)
    for (int cx = x0; cx <= x1; ++cx) {
      // Distance from the cell centre to the segment ab (closest point at parameter t).
      const Vec2 ap = cellCenter(cx, cy) - a;
      const double t = length2 > 0.0 ? std::clamp(ap.dot(ab) / length2, 0.0, 1.0) : 0.0;
      const double d = std::max(0.0, (ap - t * ab).norm() - radius);
      const std::uint8_t cost = std::min(costFromDistance(d), max_cost);
      if (cost != kFree) raiseTransientIndex(index(cx, cy), cost);
    }
}

void Costmap::markPoint(const Vec2& p) { markCircle(p, 0.0); }

void Costmap::markScan(const laser_scan_t& scan, const std::vector<Circle>& already_marked) {
  const Vec2 sensor(scan.sensor_x, scan.sensor_y);
  int last_marked = -1;
  const int beams = std::min(scan.num_ranges, static_cast<int>(scan.ranges.size()));
  for (int i = 0; i < beams; ++i) {
    const double r = scan.ranges[static_cast<std::size_t>(i)];
    if (!(r >= scan.range_min && r < scan.range_max)) continue;  // no return
    const double a = scan.sensor_yaw + scan.angle_min + i * scan.angle_increment;
    const Vec2 hit = sensor + r * Vec2(std::cos(a), std::sin(a));
    int cx, cy;
    if (!worldToCell(hit, cx, cy)) continue;
    const int cell = index(cx, cy);
    if (cell == last_marked) continue;  // neighbouring beams often hit the same cell
    if (staticDistance(cx, cy) <= params_.resolution) continue;  // the map already has it
    const bool covered = std::any_of(already_marked.begin(), already_marked.end(), [&](const Circle& c) {
      return (hit - c.center).norm() <= c.radius + params_.resolution;
    });
    if (covered) continue;
    markPoint(hit);
    last_marked = cell;
  }
}

}  // namespace hunav::planners
