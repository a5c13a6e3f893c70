#include "hunav/worldsim/physics_world.hpp"

#include <cmath>
#include <limits>

namespace hunav::worldsim {

namespace {

constexpr float kPersonMass = 70.0f;  // kg
constexpr float kRobotMass = 40.0f;   // kg
constexpr int kVelocityIterations = 8;
constexpr int kPositionIterations = 3;

b2Vec2 toB2(const Vec2& v) { return b2Vec2(static_cast<float>(v.x()), static_cast<float>(v.y())); }

b2Body* makeDisc(b2World& world, const Vec2& position, double yaw, double radius, float mass, void* tag) {
  b2BodyDef def;
  def.type = b2_dynamicBody;
  def.position = toB2(position);
  def.angle = static_cast<float>(yaw);
  def.userData.pointer = reinterpret_cast<uintptr_t>(tag);
  b2Body* body = world.CreateBody(&def);
  b2CircleShape disc;
  disc.m_radius = static_cast<float>(radius);
  b2FixtureDef fixture;
  fixture.shape = &disc;
  fixture.density = mass / static_cast<float>(kPi * radius * radius);
  fixture.friction = 0.0f;
  fixture.restitution = 0.0f;
  body->CreateFixture(&fixture);
  return body;
}

// Closest hit along a ray, optionally ignoring one body.
class ClosestHit : public b2RayCastCallback {
 public:
  ClosestHit(const b2Body* ignore, bool static_only) : ignore_(ignore), static_only_(static_only) {}
  float ReportFixture(b2Fixture* fixture, const b2Vec2&, const b2Vec2&, float fraction) override {
    if (fixture->GetBody() == ignore_) return -1.0f;  // pass through
    if (static_only_ && fixture->GetBody()->GetType() != b2_staticBody) return -1.0f;
    hit = true;
    hit_fraction = fraction;
    return fraction;  // clip the ray: later reports can only be closer
  }
  bool hit = false;
  float hit_fraction = 1.0f;

 private:
  const b2Body* ignore_;
  bool static_only_;
};

}  // namespace

// Turns Box2D's contact begin callbacks into collision events.
class PhysicsWorld::ContactRecorder : public b2ContactListener {
 public:
  explicit ContactRecorder(std::vector<collision_t>& out) : out_(out) {}
  void BeginContact(b2Contact* contact) override {
    b2Body* a = contact->GetFixtureA()->GetBody();
    b2Body* b = contact->GetFixtureB()->GetBody();
    const auto* ta = reinterpret_cast<const Tag*>(a->GetUserData().pointer);
    const auto* tb = reinterpret_cast<const Tag*>(b->GetUserData().pointer);
    if (ta == nullptr || tb == nullptr) return;
    b2WorldManifold wm;
    contact->GetWorldManifold(&wm);
    // Normal from A to B; a body "moves into" the other when its velocity has a component toward it.
    const b2Vec2 n = contact->GetManifold()->pointCount > 0 ? wm.normal : b2Vec2(1.0f, 0.0f);
    const float va = b2Dot(a->GetLinearVelocity(), n);
    const float vb = -b2Dot(b->GetLinearVelocity(), n);
    collision_t c{};
    c.kind_a = ta->kind;
    c.id_a = ta->id;
    c.kind_b = tb->kind;
    c.id_b = tb->id;
    const b2Vec2 p = contact->GetManifold()->pointCount > 0 ? wm.points[0] : a->GetPosition();
    c.x = p.x;
    c.y = p.y;
    c.normal_speed = va + vb;
    constexpr float kMoving = 1e-3f;  // m/s
    c.caused_by = (va > kMoving && vb > kMoving) ? collision_t::BY_BOTH
                  : (vb > va)                   ? collision_t::BY_B
                                                : collision_t::BY_A;
    out_.push_back(c);
  }

 private:
  std::vector<collision_t>& out_;
};

PhysicsWorld::PhysicsWorld(const Scenario& scenario)
    : scenario_(scenario),
      world_(std::make_unique<b2World>(b2Vec2(0.0f, 0.0f))),
      recorder_(std::make_unique<ContactRecorder>(contacts_)) {
  world_->SetAllowSleeping(false);
  world_->SetContactListener(recorder_.get());

  static_tag_ = Tag{collision_t::BODY_STATIC, -1};
  b2BodyDef ground_def;
  ground_def.userData.pointer = reinterpret_cast<uintptr_t>(&static_tag_);
  b2Body* ground = world_->CreateBody(&ground_def);
  for (const Shape& s : scenario.shapes) {
    if (s.kind == Shape::Kind::Circle) {
      b2CircleShape c;
      c.m_p = toB2(s.center);
      c.m_radius = static_cast<float>(s.radius);
      ground->CreateFixture(&c, 0.0f);
      continue;
    }
    // Two-sided edges: Box2D 2.4 chains are one-sided, walls must block both ways.
    const std::size_t n = s.points.size();
    const std::size_t edges = s.kind == Shape::Kind::Polygon ? n : n - 1;
    for (std::size_t i = 0; i < edges; ++i) {
      b2EdgeShape e;
      e.SetTwoSided(toB2(s.points[i]), toB2(s.points[(i + 1) % n]));
      ground->CreateFixture(&e, 0.0f);
    }
  }

  people_.reserve(scenario.agents.size());
  for (const AgentConfig& a : scenario.agents) people_.push_back(Person{nullptr, Tag{collision_t::BODY_PERSON, a.id}});
  for (std::size_t i = 0; i < people_.size(); ++i) {
    const AgentConfig& a = scenario.agents[i];
    people_[i].body = makeDisc(*world_, a.position, a.yaw, a.radius, kPersonMass, &people_[i].tag);
  }
  robot_tag_ = Tag{collision_t::BODY_ROBOT, scenario.robot.id};
  robot_ = makeDisc(*world_, scenario.robot.start, scenario.robot.start_yaw, scenario.robot.radius, kRobotMass,
                    &robot_tag_);
}

PhysicsWorld::~PhysicsWorld() = default;

void PhysicsWorld::step(double dt) {
  contacts_.clear();
  world_->Step(static_cast<float>(dt), kVelocityIterations, kPositionIterations);
}

double PhysicsWorld::rayDistance(const Vec2& from, double angle, double max_range, bool ignore_robot) const {
  const Vec2 to = from + max_range * Vec2(std::cos(angle), std::sin(angle));
  ClosestHit cb(ignore_robot ? robot_ : nullptr, false);
  world_->RayCast(&cb, toB2(from), toB2(to));
  return cb.hit ? static_cast<double>(cb.hit_fraction) * max_range : max_range;
}

bool PhysicsWorld::lineOfSight(const Vec2& a, const Vec2& b) const {
  if ((b - a).squaredNorm() <= 0.0) return true;
  ClosestHit cb(nullptr, true);
  world_->RayCast(&cb, toB2(a), toB2(b));
  return !cb.hit;
}

std::vector<Vec2> PhysicsWorld::closestObstaclePoints(const Vec2& p, double radius) const {
  std::vector<Vec2> points;
  for (const Shape& s : scenario_.shapes) {
    const Vec2 c = s.closestPoint(p);
    if ((c - p).squaredNorm() <= radius * radius) points.push_back(c);
  }
  return points;
}

}  // namespace hunav::worldsim
