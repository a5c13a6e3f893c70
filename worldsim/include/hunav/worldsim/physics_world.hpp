#pragma once
// The Box2D world: static geometry, a dynamic circle per person and for the robot, contacts, and the
// sensing that reads it (ray casts, closest obstacle points, line of sight).
#include "hunav/scenario.hpp"

#include <hunav/collision_t.hpp>

#include <box2d/box2d.h>

#include <memory>
#include <vector>

namespace hunav::worldsim {

class PhysicsWorld {
 public:
  explicit PhysicsWorld(const Scenario& scenario);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  // Bodies. People are indexed in the order of scenario.agents.
  std::size_t personCount() const { return people_.size(); }
  b2Body& person(std::size_t i) { return *people_[i].body; }
  const b2Body& person(std::size_t i) const { return *people_[i].body; }
  b2Body& robot() { return *robot_; }
  const b2Body& robot() const { return *robot_; }

  // Advances the world by dt; the contacts that began during the step are in newContacts().
  void step(double dt);
  const std::vector<collision_t>& newContacts() const { return contacts_; }

  // Distance from `from` along `angle` to the first fixture hit (ignoring the robot's own body when
  // `ignore_robot`), or max_range when nothing is hit.
  double rayDistance(const Vec2& from, double angle, double max_range, bool ignore_robot) const;
  // True when the segment a-b crosses no static geometry.
  bool lineOfSight(const Vec2& a, const Vec2& b) const;
  // Closest point of every static shape within `radius` of p.
  std::vector<Vec2> closestObstaclePoints(const Vec2& p, double radius) const;

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
};

inline Vec2 toVec(const b2Vec2& v) { return Vec2(v.x, v.y); }

}  // namespace hunav::worldsim
