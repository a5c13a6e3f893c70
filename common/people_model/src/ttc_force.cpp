#include "hunav/ttc_force.hpp"

#include <cmath>

namespace hunav {

double timeToCollision(const Vec2& x, const Vec2& v, double r) {
  const double c = x.squaredNorm() - r * r;
  if (c < 0.0) return 0.0;
  const double a = v.squaredNorm(), b = x.dot(v);
  if (b >= 0.0 || a <= 0.0) return -1.0;  // moving apart, or not moving relative to each other
  const double disc = b * b - a * c;
  if (disc <= 0.0) return -1.0;  // passing clear (or grazing)
  // (-b - sqrt(D)) / a, written without cancellation: the product of the roots is c / a.
  return c / (-b + std::sqrt(disc));
}

Vec2 ttcForce(const Vec2& x, const Vec2& v, double r, const TtcParams& p) {
  if (x.squaredNorm() > p.neighbor_distance * p.neighbor_distance) return Vec2::Zero();
  const double tau = timeToCollision(x, v, r);
  // No collision ahead, or touching already: the energy is defined for tau > 0 only. (Real couples walk
  // closer than two bodies' radii; in the simulator the world's contacts keep bodies apart.)
  if (tau <= 0.0) return Vec2::Zero();
  const double a = v.squaredNorm(), b = x.dot(v);
  const double sqrt_disc = std::sqrt(b * b - a * (x.squaredNorm() - r * r));
  const double scale = -p.k * std::exp(-tau / p.tau0) * (2.0 / tau + 1.0 / p.tau0) / (a * tau * tau);
  Vec2 f = scale * (v + (b * v - a * x) / sqrt_disc);
  const double len = f.norm();
  if (!std::isfinite(len)) return p.max_force * normalizedOrZero(x);  // tau so small the force overflows
  if (len > p.max_force) f *= p.max_force / len;
  return f;
}

}  // namespace hunav
