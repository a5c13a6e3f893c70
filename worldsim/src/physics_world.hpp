#pragma once
// The Box2D world: static geometry, a dynamic body per person and for the robot, contacts, and the
// sensing that reads it (ray casts, closest obstacle points, line of sight).
#include <box2d/box2d.h>

#include <array>
#include <cstdint>
#include <hunav/collision_t.hpp>
#include <limits>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "hunav/scenario.hpp"

namespace hunav::worldsim {

class PhysicsWorld {
 public:
  // with_robot = false: no robot body at all (the robot-free run of a counterfactual; robot() must
  // not be called then).
  explicit PhysicsWorld(const Scenario& scenario, bool with_robot = true);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  // Bodies. People are indexed in the order of scenario.agents. People are discs; the robot is a disc
  // or a box (scenario robot.shape).
  std::size_t personCount() const { return people_.size(); }
  b2Body& person(std::size_t i) { return *people_[i].body; }
  const b2Body& person(std::size_t i) const { return *people_[i].body; }
  bool hasRobot() const { return robot_ != nullptr; }
  b2Body& robot() { return *robot_; }
  const b2Body& robot() const { return *robot_; }

  // Advances the world by dt; the contacts that began during the step are in newContacts(). A contact
  // is one event per pair of bodies touching, however many of their fixtures touch (a person sliding
  // along a wall made of several edges or map rectangles is one contact until they separate); bodies
  // that touch again within 0.25 s of parting continue the same contact.
  void step(double dt);
  const std::vector<collision_t>& newContacts() const { return contacts_; }

  // Distance from `from` along `angle` to the first fixture hit (ignoring the robot's own body when
  // `ignore_robot`), or max_range when nothing is hit.
  double rayDistance(const Vec2& from, double angle, double max_range, bool ignore_robot) const;
  // rayDistance(from, first_angle + i * increment, max_range, true) for i in [0, beams), bit for bit,
  // into `out`: one broadphase query for the whole fan, and each fixture tested only against the beams
  // that can reach it (a laser scan).
  void rayFan(const Vec2& from, double first_angle, double increment, int beams, double max_range,
              std::vector<double>& out) const;
  // True when the segment a-b crosses no static geometry (people do not block it).
  bool lineOfSight(const Vec2& a, const Vec2& b) const;
  // visible[i] = lineOfSight(from[i], target), bit for bit, for many points at once: the static parts
  // are binned by their bearing from the target, so each segment tests only the parts in its
  // direction that are not farther than its start.
  void linesOfSightTo(const Vec2& target, const std::vector<Vec2>& from, std::vector<char>& visible) const;
  // Closest point of every static shape within `radius` of p, in the order of scenario.shapes, into
  // `out` (cleared first). Only the shapes whose fixtures are near p are looked at.
  void closestObstaclePoints(const Vec2& p, double radius, std::vector<Vec2>& out) const;
  std::vector<Vec2> closestObstaclePoints(const Vec2& p, double radius) const;
  // The nearest of those points (the first of equals), or false when there is none: the same as
  // picking from closestObstaclePoints, without computing the points of shapes whose bounds are
  // farther than the best so far.
  bool closestObstaclePoint(const Vec2& p, double radius, Vec2& out) const;

  // Static fixtures (edges of walls and polygons, circles) with the scenario shape each belongs to.
  struct StaticPart {
    const b2Fixture* fixture;
    int shape;  // index in scenario.shapes
  };
  const std::vector<StaticPart>& staticParts() const { return static_parts_; }

 private:
  struct Tag {
    int8_t kind;  // collision_t::BODY_*
    int32_t id;
  };
  struct Person {
    b2Body* body;
    Tag tag;
  };
  class ContactRecorder;

  const Scenario& scenario_;
  std::unique_ptr<b2World> world_;
  std::unique_ptr<ContactRecorder> recorder_;
  std::vector<Person> people_;
  b2Body* robot_ = nullptr;
  Tag robot_tag_{};
  Tag static_tag_{};
  std::vector<collision_t> contacts_;
  double time_ = 0.0;  // s, simulated by step()
  // Static geometry alone in its own tree and in a grid, so that obstacle and line-of-sight queries
  // never walk through the crowd's proxies.
  std::vector<StaticPart> static_parts_;
  b2DynamicTree static_tree_;
  // Uniform grid over the static geometry: per cell, the shapes that may be within `radius` of a point
  // of the cell (obstacle points look up one cell), sorted (compressed rows).
  struct StaticGrid {
    double x0 = 0.0, y0 = 0.0, cell = 1.0, radius = 0.0;
    int nx = 0, ny = 0;
    std::vector<std::uint32_t> shape_start, shapes;
    bool cellOf(const Vec2& p, int& ix, int& iy) const;
  };
  void buildGrid(double radius);
  StaticGrid grid_;
  std::vector<std::array<double, 4>> shape_bounds_;  // per scenario shape: x0, y0, x1, y1
  // Scratch space reused across calls (single-threaded).
  struct SightEntry {
    std::uint32_t bin;
    std::uint32_t part;
    float distance;  // least distance of the part to the target, m
  };
  mutable std::vector<int> candidate_shapes_;
  mutable std::vector<const b2Fixture*> fan_fixtures_;
  mutable std::vector<float> fan_best_;
  mutable std::vector<b2RayCastInput> fan_inputs_;
  // The beam directions (cos, sin) of the last fan, reused while its angles are the same (a robot
  // that does not turn: no cos/sin per beam).
  mutable std::vector<Vec2> fan_dirs_;
  mutable double fan_dirs_first_ = std::numeric_limits<double>::quiet_NaN();
  mutable double fan_dirs_increment_ = std::numeric_limits<double>::quiet_NaN();
  // rayFan's steps.
  void collectFanFixtures(const Vec2& from, double max_range) const;
  void updateFanDirections(std::size_t n, double first_angle, double increment) const;
  mutable std::vector<std::uint32_t> sight_parts_, sight_start_, sight_fill_;
  mutable std::vector<SightEntry> sight_entries_, sight_sorted_;
  // linesOfSightTo's steps.
  void collectSightParts(const Vec2& target, double reach) const;
  void binSightParts(const Vec2& target) const;
  void testSightsInBins(const Vec2& target, const std::vector<Vec2>& from, std::vector<char>& visible) const;
};

inline Vec2 toVec(const b2Vec2& v) { return Vec2(v.x, v.y); }

}  // namespace hunav::worldsim
