#include "hunav/realism/groups.hpp"

#include <algorithm>
#include <numeric>
#include <set>
#include <vector>

namespace hunav::realism {

namespace {

// Union-find over person ids, the smallest id the root.
struct Components {
  std::map<int, int> parent;
  int find(int x) {
    auto it = parent.find(x);
    if (it == parent.end()) return parent[x] = x;
    if (it->second == x) return x;
    return it->second = find(it->second);
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace

GroupIds detectGroups(const Dataset& d, const GroupRule& rule) {
  // For every pair recorded together, the running stretch: its length in frame steps and the sum of
  // the velocity differences, ended when they part or a frame is missing.
  struct Stretch {
    std::int64_t last_frame = -2;
    int steps = 0;
    double speed_difference = 0.0;
  };
  std::map<std::pair<int, int>, Stretch> running;
  std::set<std::pair<int, int>> pairs;
  const double interval = d.frame_interval;
  const int min_steps = static_cast<int>(std::ceil(rule.min_duration / interval - 1e-9));
  for (const auto& [frame, people] : d.frames) {
    const auto next = d.frames.find(frame + 1);
    for (auto a = people.begin(); a != people.end(); ++a) {
      for (auto b = std::next(a); b != people.end(); ++b) {
        const std::pair<int, int> key(a->first, b->first);
        if ((a->second - b->second).norm() > rule.max_distance) {
          running.erase(key);
          continue;
        }
        Stretch& s = running[key];
        if (s.last_frame != frame - 1) s = Stretch{};
        s.last_frame = frame;
        // The velocity difference over [frame, frame + 1] when both are there in the next frame.
        if (next == d.frames.end()) continue;
        const auto na = next->second.find(a->first), nb = next->second.find(b->first);
        if (na == next->second.end() || nb == next->second.end()) continue;
        if ((na->second - nb->second).norm() > rule.max_distance) continue;  // parts in the next frame
        const Vec2 va = (na->second - a->second) / interval, vb = (nb->second - b->second) / interval;
        s.steps += 1;
        s.speed_difference += (va - vb).norm();
        if (s.steps >= min_steps && s.speed_difference / s.steps <= rule.max_speed_difference) pairs.insert(key);
      }
    }
  }
  Components groups;
  for (const auto& [a, b] : pairs) groups.join(a, b);
  GroupIds out;
  for (const auto& [a, b] : pairs) {
    out[a] = groups.find(a);
    out[b] = groups.find(b);
  }
  return out;
}

}  // namespace hunav::realism
