#pragma once
// The scenarios shipped in scenarios/, loaded from the source tree (HUNAV_SOURCE_DIR, defined for
// every test binary).
#include <string>

#include "hunav/scenario.hpp"

namespace hunav::testing {

inline std::string scenarioFile(const std::string& name) {
  return std::string(HUNAV_SOURCE_DIR) + "/scenarios/" + name + ".yaml";
}

inline Scenario shippedScenario(const std::string& name, long long seed_override = -1) {
  return loadScenario(scenarioFile(name), seed_override);
}

inline Scenario passing() { return shippedScenario("passing"); }

// A straight wall from a to b (an open polyline), as a scenario's map.walls entry.
inline Shape wall(const Vec2& a, const Vec2& b) {
  Shape s;
  s.kind = Shape::Kind::Polyline;
  s.points = {a, b};
  return s;
}

}  // namespace hunav::testing
