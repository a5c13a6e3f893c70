#pragma once
// Giving way (people.give_way). Two people face to face in a passage only one of them fits through,
// or a person and the robot in a door, hold each other still: the social force of each pushes the
// other back as hard as its goal pulls it on, and nobody moves for ever. People resolve it: one steps
// back to where the other can pass and waits. Here a person held up for kStuckSeconds (a quarter of
// its pace or less) while somebody stands right in its way does the same (manager/README.md, "Giving
// way"): it walks back along its own recent trail to the first place with room beside the trail for
// the other to pass, steps aside there, waits until the other has passed (or kWaitAtMostSeconds), and
// walks on. Between two people the one with the higher id gives way (the other would keep pushing),
// after 2 x kStuckSeconds either does; a person always gives way to the robot.
#include <optional>

#include "hunav/manager/tick_context.hpp"

namespace hunav::manager {

inline constexpr double kStuckSeconds = 4.0;  // held up this long before giving way
// Held up: it covered less than kProgressShare of the way its desired speed would have taken it (and
// less than kProgressMove); someone ahead walking on the same way at that share is not in the way.
inline constexpr double kProgressShare = 0.25;
inline constexpr double kProgressMove = 0.2;  // m
inline constexpr double kTrailStep = 0.2;     // m between trail points
inline constexpr double kBlockGap = 0.5;      // m between bodies: the other stands in the way
inline constexpr double kPassGap = 0.15;      // m the other keeps from the waiting person as it passes
inline constexpr double kStepBackAtMostSeconds = 10.0;
inline constexpr double kWaitAtMostSeconds = 8.0;
// The place it steps back to keeps its radius + the other's + kPassGap + kRefugeFromOther from the
// other, and kRefugeFromOther more each time it gives way again to the same one (within kAgainSeconds
// of walking on, the other not passed; at most kMaxRepeats times more).
inline constexpr double kRefugeFromOther = 0.5;
inline constexpr double kAgainSeconds = 15.0;
inline constexpr int kMaxRepeats = 4;

// Records the person's trail and decides: the point it walks to instead of `goal` while it gives
// way, or nullopt to walk on to its goal. Only the person's own memory changes.
std::optional<Vec2> giveWayTarget(TickContext& c, const Vec2& goal, double goal_radius);

}  // namespace hunav::manager
