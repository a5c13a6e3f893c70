#pragma once
// Groups in a recording (realism/README.md, "Groups"): two people walk together when, for a stretch
// of consecutive frames in which both are recorded, they stay within max_distance of each other with
// a mean velocity difference of at most max_speed_difference, for at least min_duration seconds; a
// group is a connected set of such pairs. The recordings carry no group labels: this rule is ours.
#include <map>

#include "hunav/realism/tracks.hpp"

namespace hunav::realism {

struct GroupRule {
  double max_distance = 1.2;          // m, between the two centres in every frame of the stretch
  double max_speed_difference = 0.3;  // m/s, mean over the stretch of |v_i - v_j| (finite differences)
  double min_duration = 4.0;          // s, the stretch's length (frames - 1) * frame interval
};

// Person id -> group id (the smallest id of the group), for the people in a group.
using GroupIds = std::map<int, int>;

GroupIds detectGroups(const Dataset& d, const GroupRule& rule = GroupRule{});

}  // namespace hunav::realism
