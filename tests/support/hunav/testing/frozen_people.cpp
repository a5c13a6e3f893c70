#include "hunav/testing/frozen_people.hpp"

#include <algorithm>

namespace hunav::testing {

void FrozenPeople::add(double t, int id, const Vec2& position, int behavior_state, const std::optional<Vec2>& goal,
                       double goal_radius) {
  auto [it, first] = anchors_.try_emplace(id, Anchor{t, position});
  Anchor& anchor = it->second;
  const bool far_from_goal = goal && (position - *goal).norm() > goal_radius + kFrozenFromGoal;
  const bool moved = (position - anchor.position).norm() > kFrozenMove;
  if (first || moved || !far_from_goal || behavior_state != 0) anchor = {t, position};  // a fresh start
  Spell& best = longest_[id];
  if (t - anchor.t > best.seconds) best = {t - anchor.t, anchor.t, t, anchor.position, position, goal};
}

double FrozenPeople::longestSeconds() const {
  double s = 0.0;
  for (const auto& [id, spell] : longest_) s = std::max(s, spell.seconds);
  return s;
}

int FrozenPeople::frozenFor(double limit) const {
  return static_cast<int>(std::count_if(longest_.begin(), longest_.end(),
                                        [&](const auto& entry) { return entry.second.seconds >= limit; }));
}

}  // namespace hunav::testing
