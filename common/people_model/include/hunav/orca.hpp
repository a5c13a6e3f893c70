#pragma once
// Optimal reciprocal collision avoidance (ORCA; J. van den Berg, S. J. Guy, M. Lin, D. Manocha,
// "Reciprocal n-body collision avoidance", Robotics Research, Springer 2011), written here from the
// paper: each neighbour within reach gives a half-plane of allowed velocities, and the person takes
// the velocity closest to its preferred one inside all of them and its speed disc. One
// implementation serves the manager (moving people, docs/people_models.md) and hunav_realism.
#include <vector>

#include "hunav/geometry.hpp"

namespace hunav {

struct OrcaParams {
  double neighbor_distance = 5.0;      // m, neighbours farther than this are not considered
  int max_neighbors = 10;              // the nearest this many within neighbor_distance
  double time_horizon = 2.0;           // s, tau: velocities safe from people for this long
  double obstacle_time_horizon = 1.0;  // s, the same for static obstacles
  double radius = -1.0;                // m, the radius avoided with (< 0: the person's own)
  double responsibility = 0.5;         // share of the avoidance a person takes (0.5: reciprocal, the paper)
  double relaxation_time = 0.0;        // s, velocity reaches the ORCA velocity with this time constant (0: at once)
};

// The allowed side of a line: velocities v with normal . (v - point) >= 0.
struct HalfPlane {
  Vec2 point = Vec2::Zero();
  Vec2 normal = Vec2::UnitX();  // unit
  bool contains(const Vec2& v, double slack = 0.0) const { return normal.dot(v - point) >= -slack; }
  // How far v lies outside (negative: inside).
  double violation(const Vec2& v) const { return -normal.dot(v - point); }
};

// The ORCA half-plane of a person at `position` with velocity `velocity` and radius `radius` against
// a neighbour (`other_*`), the person taking `responsibility` of the avoidance (section 4 of the
// paper, 1/2 there): u is the smallest change of the relative velocity that leaves the velocity
// obstacle of horizon `tau` (the cone toward the neighbour cut off by the disc of the neighbour's
// position / tau, radius (r_a + r_b) / tau), n its outward normal; the person must move
// `responsibility` of u: normal n through velocity + responsibility * u. Bodies that already
// overlap use the velocity obstacle of one step `dt` instead (they separate within the step).
HalfPlane orcaHalfPlane(const Vec2& position, const Vec2& velocity, double radius, const Vec2& other_position,
                        const Vec2& other_velocity, double other_radius, double tau, double responsibility, double dt);

// A static obstacle whose nearest point to the person is `closest` (a point of a wall segment, or an
// obstacle point the world sent): the half-plane of velocities that keep the person's disc away from
// the line through `closest` perpendicular to the direction to it for `tau` seconds,
// n . v >= -(d - r) / tau with n the unit vector from the obstacle to the person and d the distance.
// That line separates the person from a convex obstacle (the nearest point's tangent), so every
// velocity allowed is safe from the whole segment: the cone of the paper's segment obstacle,
// approximated on the safe side by this one line (the paper's obstacles take full responsibility,
// as here). A person already within r of the point may not come closer: n . v >= 0.
HalfPlane obstacleHalfPlane(const Vec2& position, double radius, const Vec2& closest, double tau);

// The velocity closest to `preferred` inside the disc |v| <= max_speed and every half-plane. The
// first `hard` planes (obstacles) are kept whenever possible; when the others cannot all hold (a
// dense crowd), the velocity that exceeds the others least (the smallest largest violation) is
// taken, as the paper's section 5.2 does. Deterministic: the planes are taken in the order given.
Vec2 solveOrcaVelocity(const std::vector<HalfPlane>& planes, std::size_t hard, const Vec2& preferred, double max_speed);

}  // namespace hunav
