#include "people_give_way.hpp"

#include <cmath>
#include <limits>

#include "people_routes.hpp"

namespace hunav::manager {

namespace {

constexpr std::int64_t seconds(double s) { return static_cast<std::int64_t>(s * 1e6); }

// Who stands in the way: the nearest body (a person or the robot) within kBlockGap of the person's
// body, on the side it walks to.
struct Blocker {
  bool found = false;
  bool is_robot = false;
  int id = 0;
  Vec2 position = Vec2::Zero();
  double radius = 0.0;
};

Blocker blockerAhead(const TickContext& c, const Vec2& here, const Vec2& heading) {
  Blocker best;
  double best_gap = kBlockGap;
  const double len = heading.norm();
  const Vec2 ahead = len > 0.0 ? Vec2(heading / len) : Vec2::Zero();
  auto consider = [&](const SfmBody& b, bool is_robot) {
    const Vec2 d = b.position - here;
    const double gap = d.norm() - b.radius - c.in.radius;
    if (gap >= best_gap || d.dot(ahead) <= 0.0) return;
    // Somebody walking on the same way (a queue) is followed, not given way to.
    if (b.velocity.dot(ahead) >= kProgressShare * c.in.desired_speed) return;
    best_gap = gap;
    best = Blocker{true, is_robot, b.id, b.position, b.radius};
  };
  for (std::size_t j = 0; j < c.snap.agents.size(); ++j)
    if (j != c.index) consider(c.snap.agents[j], false);
  if (c.snap.robotState() != nullptr) consider(c.snap.robot, true);
  return best;
}

// Where the blocker is now (nullopt: it left the world).
std::optional<Vec2> blockerPosition(const TickContext& c, const GiveWayMemory& g) {
  if (g.blocker_is_robot) {
    if (c.snap.robotState() == nullptr) return std::nullopt;
    return c.snap.robot.position;
  }
  const int j = c.snap.indexOf(g.blocker);
  if (j < 0) return std::nullopt;
  return c.snap.agents[static_cast<std::size_t>(j)].position;
}

// The trail point `back` steps before the newest (0: the newest; back < trail_size).
const Vec2& trailPoint(const GiveWayMemory& g, int back) {
  constexpr int n = GiveWayMemory::kTrailPoints;
  return g.trail[static_cast<std::size_t>(((g.trail_head - 1 - back) % n + n) % n)];
}

// The first place back along the trail where the person can stand beside its trail with room for a
// body of radius `other` to pass between it and the trail's far side: a trail point p, moved sideways
// by the person's radius + other + kPassGap, where the person fits, reachable in a straight line from
// p, and free of the other people. nullopt: none on the trail.
std::optional<Vec2> refugeOnTrail(const TickContext& c, const GiveWayMemory& g, const Vec2& other_at, double other,
                                  int repeats) {
  const RouteMap& routes = *c.snap.routes;
  const double r = c.in.radius;
  const double aside = r + other + kPassGap;
  // Far enough from the other that it can pass, farther each time it did not.
  const double away = aside + kRefugeFromOther * (1 + repeats);
  auto freeOfPeople = [&](const Vec2& spot) {
    for (std::size_t j = 0; j < c.snap.agents.size(); ++j) {
      if (j == c.index) continue;
      const SfmBody& b = c.snap.agents[j];
      if ((b.position - spot).norm() < b.radius + r + kPassGap) return false;
    }
    return true;
  };
  for (int k = 1; k < g.trail_size; ++k) {
    const Vec2 p = trailPoint(g, k), newer = trailPoint(g, k - 1);
    const Vec2 along = newer - p;
    if (along.norm() <= 0.0) continue;
    const Vec2 normal = Vec2(-along.y(), along.x()) / along.norm();
    // The other walks along the trail: p must leave it room there.
    if (routes.clearance(p) < other) continue;
    for (const double side : {1.0, -1.0}) {
      const Vec2 spot = p + side * aside * normal;
      if ((spot - other_at).norm() >= away && routes.clearance(spot) >= r && routes.clearLine(p, spot, r) &&
          freeOfPeople(spot))
        return spot;
    }
  }
  return std::nullopt;
}

void remember(GiveWayMemory& g, const Vec2& here) {
  if (g.trail_size > 0) {
    if ((here - trailPoint(g, 0)).norm() < kTrailStep) return;
  }
  g.trail[static_cast<std::size_t>(g.trail_head)] = here;
  g.trail_head = (g.trail_head + 1) % GiveWayMemory::kTrailPoints;
  if (g.trail_size < GiveWayMemory::kTrailPoints) ++g.trail_size;
}

void walkOn(GiveWayMemory& g, const Vec2& here, std::int64_t now) {
  g.phase = GiveWayMemory::Phase::Walking;
  g.has_anchor = true;
  g.anchor = here;
  g.anchor_utime = now;
}

}  // namespace

std::optional<Vec2> giveWayTarget(TickContext& c, const Vec2& goal, double goal_radius) {
  GiveWayMemory& g = c.memory.give_way;
  const Vec2 here(c.in.x, c.in.y);
  const std::int64_t now = c.snap.request->utime;
  // Where the person heads: its route's waypoint, or the goal in sight.
  const Vec2 toward = c.memory.has_route && !c.memory.route_direct ? c.memory.route_waypoint : goal;
  const Vec2 heading = toward - here;

  switch (g.phase) {
    case GiveWayMemory::Phase::Walking: {
      remember(g, here);
      const bool at_goal = (goal - here).norm() <= goal_radius + 0.5;
      if (!g.has_anchor || at_goal || now < g.anchor_utime) {
        walkOn(g, here, now);
        return std::nullopt;
      }
      // Held up: in the last kStuckSeconds (or longer, while it waits its turn) it covered less than
      // kProgressShare of the way its desired speed would have taken it (at least kProgressMove).
      const std::int64_t still = now - g.anchor_utime;
      if (still < seconds(kStuckSeconds) || now < g.next_check_utime) return std::nullopt;
      const double expected = kProgressShare * c.in.desired_speed * static_cast<double>(still) * 1e-6;
      if ((here - g.anchor).norm() > std::max(kProgressMove, expected)) {
        walkOn(g, here, now);  // it progresses: a fresh window
        return std::nullopt;
      }
      const Blocker b = blockerAhead(c, here, heading);
      if (!b.found) {
        walkOn(g, here, now);  // held up by something else (a wall, a crowd): a fresh window
        return std::nullopt;
      }
      // Between two people the higher id gives way; after twice as long either does.
      if (!b.is_robot && b.id < c.in.id && still < seconds(2.0 * kStuckSeconds)) return std::nullopt;
      const bool again = g.repeats >= 0 && g.blocker == b.id && g.blocker_is_robot == b.is_robot &&
                         now - g.phase_utime < seconds(kAgainSeconds);
      const int repeats = again ? std::min(g.repeats + 1, kMaxRepeats) : 0;
      const std::optional<Vec2> refuge = refugeOnTrail(c, g, b.position, b.radius, repeats);
      if (!refuge) {
        g.next_check_utime = now + seconds(1.0);
        return std::nullopt;
      }
      g.phase = GiveWayMemory::Phase::SteppingBack;
      g.refuge = *refuge;
      g.blocker = b.id;
      g.blocker_is_robot = b.is_robot;
      g.repeats = repeats;
      g.phase_utime = now;
      return g.refuge;
    }
    case GiveWayMemory::Phase::SteppingBack:
      if ((here - g.refuge).norm() > 0.15 && now - g.phase_utime < seconds(kStepBackAtMostSeconds)) return g.refuge;
      g.phase = GiveWayMemory::Phase::Waiting;
      g.phase_utime = now;
      return g.refuge;
    case GiveWayMemory::Phase::Waiting: {
      // Walk on once the other has passed (it is behind, on the side the person came from), has
      // left, or after kWaitAtMostSeconds.
      const std::optional<Vec2> other = blockerPosition(c, g);
      const bool passed = !other || (*other - here).dot(heading) < 0.0 || (*other - here).norm() > 3.0;
      if (!passed && now - g.phase_utime < seconds(kWaitAtMostSeconds)) return g.refuge;
      if (passed) g.repeats = -1;  // the next give way, even to the same one, starts afresh
      g.phase_utime = now;         // when it walked on (kAgainSeconds)
      walkOn(g, here, now);
      return std::nullopt;
    }
  }
  return std::nullopt;
}

}  // namespace hunav::manager
