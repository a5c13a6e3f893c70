#include "physics_world.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>

namespace hunav::worldsim {

namespace {

constexpr float kPersonMass = 70.0f;  // kg
constexpr float kRobotMass = 40.0f;   // kg
constexpr int kVelocityIterations = 8;
constexpr int kPositionIterations = 3;

b2Vec2 toB2(const Vec2& v) { return b2Vec2(static_cast<float>(v.x()), static_cast<float>(v.y())); }

b2Body* makeBody(b2World& world, const Vec2& position, double yaw, const b2Shape& shape, double area, float mass,
                 void* tag) {
  b2BodyDef def;
  def.type = b2_dynamicBody;
  def.position = toB2(position);
  def.angle = static_cast<float>(yaw);
  def.userData.pointer = reinterpret_cast<uintptr_t>(tag);
  b2Body* body = world.CreateBody(&def);
  b2FixtureDef fixture;
  fixture.shape = &shape;
  fixture.density = mass / static_cast<float>(area);
  fixture.friction = 0.0f;
  fixture.restitution = 0.0f;
  body->CreateFixture(&fixture);
  return body;
}

b2Body* makeDisc(b2World& world, const Vec2& position, double yaw, double radius, float mass, void* tag) {
  b2CircleShape disc;
  disc.m_radius = static_cast<float>(radius);
  return makeBody(world, position, yaw, disc, kPi * radius * radius, mass, tag);
}

constexpr double kGridCell = 1.0;  // m, cells of the static grid (larger for huge maps)
constexpr std::size_t kMaxGridCells = 1u << 22;
constexpr double kGridMargin = 1e-3;  // m, bounds grow by this against rounding

// Stops at the first static fixture the ray crosses (any hit blocks the line of sight).
class AnyHit {
 public:
  AnyHit(const b2DynamicTree& tree, const std::vector<PhysicsWorld::StaticPart>& parts) : tree_(tree), parts_(parts) {}
  float RayCastCallback(const b2RayCastInput& input, int32 proxy) {
    const auto index = reinterpret_cast<std::uintptr_t>(tree_.GetUserData(proxy));
    b2RayCastOutput out;
    if (parts_[index].fixture->RayCast(&out, input, 0)) {
      hit = true;
      return 0.0f;  // terminate
    }
    return input.maxFraction;
  }
  bool hit = false;

 private:
  const b2DynamicTree& tree_;
  const std::vector<PhysicsWorld::StaticPart>& parts_;
};

// The static parts whose bounds overlap a box.
class PartsInBox {
 public:
  PartsInBox(const b2DynamicTree& tree, std::vector<std::uint32_t>& out) : tree_(tree), out_(out) {}
  bool QueryCallback(int32 proxy) {
    out_.push_back(static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(tree_.GetUserData(proxy))));
    return true;
  }

 private:
  const b2DynamicTree& tree_;
  std::vector<std::uint32_t>& out_;
};

// Every fixture in the world's broadphase within a box.
class FixturesInBox : public b2QueryCallback {
 public:
  explicit FixturesInBox(std::vector<const b2Fixture*>& out) : out_(out) {}
  bool ReportFixture(b2Fixture* fixture) override {
    out_.push_back(fixture);
    return true;
  }

 private:
  std::vector<const b2Fixture*>& out_;
};

// Distance between two axis-aligned boxes (0 when they overlap).
double boxDistance(double ax0, double ay0, double ax1, double ay1, double bx0, double by0, double bx1, double by1) {
  const double dx = std::max({0.0, bx0 - ax1, ax0 - bx1});
  const double dy = std::max({0.0, by0 - ay1, ay0 - by1});
  return std::hypot(dx, dy);
}

// Collects the shapes of the static fixtures whose (fattened) bounds overlap a box.
class ShapesInBox {
 public:
  ShapesInBox(const b2DynamicTree& tree, const std::vector<PhysicsWorld::StaticPart>& parts, std::vector<int>& out)
      : tree_(tree), parts_(parts), out_(out) {}
  bool QueryCallback(int32 proxy) {
    const auto index = reinterpret_cast<std::uintptr_t>(tree_.GetUserData(proxy));
    out_.push_back(parts_[index].shape);
    return true;
  }

 private:
  const b2DynamicTree& tree_;
  const std::vector<PhysicsWorld::StaticPart>& parts_;
  std::vector<int>& out_;
};

// Closest hit along a ray, optionally ignoring one body.
class ClosestHit : public b2RayCastCallback {
 public:
  explicit ClosestHit(const b2Body* ignore) : ignore_(ignore) {}
  float ReportFixture(b2Fixture* fixture, const b2Vec2&, const b2Vec2&, float fraction) override {
    if (fixture->GetBody() == ignore_) return -1.0f;  // pass through
    hit = true;
    hit_fraction = fraction;
    return fraction;  // clip the ray: later reports can only be closer
  }
  bool hit = false;
  float hit_fraction = 1.0f;

 private:
  const b2Body* ignore_;
};

}  // namespace

// Turns Box2D's contact callbacks into collision events: one event when a pair of bodies starts
// touching. Box2D reports a begin and an end per pair of fixtures (a person sliding along a wall of
// several edges ends one and begins the next), and bodies pressed together may part by a hair for a
// step or two; so touching fixture pairs are counted per body pair, and a pair that touches again
// within kRejoin of parting continues its contact.
class PhysicsWorld::ContactRecorder : public b2ContactListener {
 public:
  static constexpr double kRejoin = 0.25;  // s of simulation time

  explicit ContactRecorder(std::vector<collision_t>& out) : out_(out) {}
  // Called before each step with the simulation time it starts at.
  void beginStep(double now) {
    now_ = now;
    began_.clear();
    for (auto it = parted_.begin(); it != parted_.end();)
      it = now_ - it->second > kRejoin ? parted_.erase(it) : std::next(it);
  }
  void EndContact(b2Contact* contact) override {
    const BodyPair pair = pairOf(contact);
    const auto it = touching_.find(pair);
    if (it != touching_.end() && --it->second == 0) {
      touching_.erase(it);
      parted_[pair] = now_;
    }
  }
  void BeginContact(b2Contact* contact) override {
    b2Body* a = contact->GetFixtureA()->GetBody();
    b2Body* b = contact->GetFixtureB()->GetBody();
    const auto* ta = reinterpret_cast<const Tag*>(a->GetUserData().pointer);
    const auto* tb = reinterpret_cast<const Tag*>(b->GetUserData().pointer);
    if (ta == nullptr || tb == nullptr) return;
    const BodyPair pair = pairOf(contact);
    if (++touching_[pair] > 1) return;  // these bodies already touch elsewhere
    if (const auto parted = parted_.find(pair); parted != parted_.end()) {
      parted_.erase(parted);
      return;  // together again right after parting: the same contact
    }
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
                  : (vb > va)                    ? collision_t::BY_B
                                                 : collision_t::BY_A;
    out_.push_back(c);
    began_.emplace(pair, out_.size() - 1);
  }
  // After the solver (the step's, and the time-of-impact sub-steps'): the impulse that parted a pair
  // whose contact began in this step goes to its event. Later steps' impulses are not the collision's.
  void PostSolve(b2Contact* contact, const b2ContactImpulse* impulse) override {
    const auto it = began_.find(pairOf(contact));
    if (it == began_.end()) return;
    double sum = 0.0;
    for (int32 i = 0; i < impulse->count; ++i) sum += static_cast<double>(impulse->normalImpulses[i]);
    out_[it->second].impulse += sum;
  }

 private:
  using BodyPair = std::pair<const b2Body*, const b2Body*>;
  static BodyPair pairOf(const b2Contact* contact) {
    const b2Body* a = contact->GetFixtureA()->GetBody();
    const b2Body* b = contact->GetFixtureB()->GetBody();
    return std::less<const b2Body*>()(a, b) ? BodyPair(a, b) : BodyPair(b, a);
  }
  std::vector<collision_t>& out_;
  std::map<BodyPair, int> touching_;       // fixture contacts touching, per body pair
  std::map<BodyPair, double> parted_;      // pairs that stopped touching, and when
  std::map<BodyPair, std::size_t> began_;  // pairs whose event began this step, and its index in out_
  double now_ = 0.0;
};

PhysicsWorld::PhysicsWorld(const Scenario& scenario, bool with_robot)
    : scenario_(scenario),
      world_(std::make_unique<b2World>(b2Vec2(0.0f, 0.0f))),
      recorder_(std::make_unique<ContactRecorder>(contacts_)) {
  world_->SetAllowSleeping(false);
  world_->SetContactListener(recorder_.get());

  static_tag_ = Tag{collision_t::BODY_STATIC, -1};
  b2BodyDef ground_def;
  ground_def.userData.pointer = reinterpret_cast<uintptr_t>(&static_tag_);
  b2Body* ground = world_->CreateBody(&ground_def);
  for (std::size_t si = 0; si < scenario.shapes.size(); ++si) {
    const Shape& s = scenario.shapes[si];
    const int shape_index = static_cast<int>(si);
    if (s.kind == Shape::Kind::Circle) {
      b2CircleShape c;
      c.m_p = toB2(s.center);
      c.m_radius = static_cast<float>(s.radius);
      static_parts_.push_back(StaticPart{ground->CreateFixture(&c, 0.0f), shape_index});
      continue;
    }
    // Two-sided edges: Box2D 2.4 chains are one-sided, walls must block both ways. Polygons stay
    // edges too: a polygon may be a room with the robot inside.
    const std::size_t n = s.points.size();
    const std::size_t edges = s.kind == Shape::Kind::Polygon ? n : n - 1;
    for (std::size_t i = 0; i < edges; ++i) {
      b2EdgeShape e;
      e.SetTwoSided(toB2(s.points[i]), toB2(s.points[(i + 1) % n]));
      static_parts_.push_back(StaticPart{ground->CreateFixture(&e, 0.0f), shape_index});
    }
  }
  for (std::size_t i = 0; i < static_parts_.size(); ++i) {
    b2AABB box;
    static_parts_[i].fixture->GetShape()->ComputeAABB(&box, ground->GetTransform(), 0);
    static_tree_.CreateProxy(box, reinterpret_cast<void*>(static_cast<std::uintptr_t>(i)));
  }
  buildGrid(scenario.obstacle_radius);
  shape_bounds_.reserve(scenario.shapes.size());
  for (const Shape& shape : scenario.shapes) {
    Vec2 lo, hi;
    shape.bounds(lo, hi);
    shape_bounds_.push_back({lo.x(), lo.y(), hi.x(), hi.y()});
  }

  people_.reserve(scenario.agents.size());
  for (const AgentConfig& a : scenario.agents) people_.push_back(Person{nullptr, Tag{collision_t::BODY_PERSON, a.id}});
  for (std::size_t i = 0; i < people_.size(); ++i) {
    const AgentConfig& a = scenario.agents[i];
    people_[i].body = makeDisc(*world_, a.position, a.yaw, a.radius, kPersonMass, &people_[i].tag);
  }
  robot_tag_ = Tag{collision_t::BODY_ROBOT, scenario.robot.id};
  if (!with_robot) return;
  const RobotConfig& rc = scenario.robot;
  if (rc.shape == RobotShape::Box) {
    b2PolygonShape box;
    box.SetAsBox(static_cast<float>(rc.length / 2), static_cast<float>(rc.width / 2));
    robot_ = makeBody(*world_, rc.start, rc.start_yaw, box, rc.length * rc.width, kRobotMass, &robot_tag_);
  } else {
    robot_ = makeDisc(*world_, rc.start, rc.start_yaw, rc.radius, kRobotMass, &robot_tag_);
  }
}

PhysicsWorld::~PhysicsWorld() = default;

bool PhysicsWorld::StaticGrid::cellOf(const Vec2& p, int& ix, int& iy) const {
  const double fx = (p.x() - x0) / cell, fy = (p.y() - y0) / cell;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < nx && fy < ny)) return false;
  ix = static_cast<int>(fx);
  iy = static_cast<int>(fy);
  return true;
}

void PhysicsWorld::buildGrid(double radius) {
  StaticGrid& g = grid_;
  g = StaticGrid{};
  g.radius = radius;
  if (static_parts_.empty()) return;
  std::vector<b2AABB> boxes(static_parts_.size());
  for (std::size_t i = 0; i < static_parts_.size(); ++i)
    static_parts_[i].fixture->GetShape()->ComputeAABB(&boxes[i], static_parts_[i].fixture->GetBody()->GetTransform(),
                                                      0);
  b2AABB all = boxes.front();
  for (const b2AABB& b : boxes) all.Combine(b);
  // The grid reaches `radius` beyond the geometry, so every point with an obstacle point is inside it.
  const double pad = radius + kGridMargin;
  const double x0 = all.lowerBound.x - pad, y0 = all.lowerBound.y - pad;
  const double w = all.upperBound.x + pad - x0, h = all.upperBound.y + pad - y0;
  g.cell = std::max(kGridCell, std::sqrt(w * h / static_cast<double>(kMaxGridCells)));
  g.x0 = x0;
  g.y0 = y0;
  g.nx = std::max(1, static_cast<int>(std::ceil(w / g.cell)));
  g.ny = std::max(1, static_cast<int>(std::ceil(h / g.cell)));

  // (cell, item) pairs, then compressed rows.
  auto compress = [&](std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs, std::vector<std::uint32_t>& start,
                      std::vector<std::uint32_t>& items) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    start.assign(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny) + 1, 0);
    for (const auto& p : pairs) ++start[p.first + 1];
    for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    items.resize(pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) items[k] = pairs[k].second;
  };
  auto cellRange = [&](double lo, double hi, double origin, int n, int& i0, int& i1) {
    i0 = std::clamp(static_cast<int>(std::floor((lo - origin) / g.cell)), 0, n - 1);
    i1 = std::clamp(static_cast<int>(std::floor((hi - origin) / g.cell)), 0, n - 1);
  };
  std::vector<std::pair<std::uint32_t, std::uint32_t>> shape_pairs;
  for (std::size_t i = 0; i < static_parts_.size(); ++i) {
    const b2AABB& b = boxes[i];
    const double bx0 = b.lowerBound.x - kGridMargin, by0 = b.lowerBound.y - kGridMargin;
    const double bx1 = b.upperBound.x + kGridMargin, by1 = b.upperBound.y + kGridMargin;
    int ix0, ix1, iy0, iy1;
    cellRange(bx0 - radius, bx1 + radius, g.x0, g.nx, ix0, ix1);
    cellRange(by0 - radius, by1 + radius, g.y0, g.ny, iy0, iy1);
    for (int iy = iy0; iy <= iy1; ++iy) {
      for (int ix = ix0; ix <= ix1; ++ix) {
        const double cx0 = g.x0 + ix * g.cell, cy0 = g.y0 + iy * g.cell;
        if (boxDistance(cx0, cy0, cx0 + g.cell, cy0 + g.cell, bx0, by0, bx1, by1) <= radius)
          shape_pairs.emplace_back(static_cast<std::uint32_t>(iy * g.nx + ix),
                                   static_cast<std::uint32_t>(static_parts_[i].shape));
      }
    }
  }
  compress(shape_pairs, g.shape_start, g.shapes);
}

void PhysicsWorld::step(double dt) {
  contacts_.clear();
  recorder_->beginStep(time_);
  world_->Step(static_cast<float>(dt), kVelocityIterations, kPositionIterations);
  time_ += dt;
}

double PhysicsWorld::rayDistance(const Vec2& from, double angle, double max_range, bool ignore_robot) const {
  const Vec2 to = from + max_range * Vec2(std::cos(angle), std::sin(angle));
  ClosestHit cb(ignore_robot ? robot_ : nullptr);
  world_->RayCast(&cb, toB2(from), toB2(to));
  return cb.hit ? static_cast<double>(cb.hit_fraction) * max_range : max_range;
}

void PhysicsWorld::rayFan(const Vec2& from, double first_angle, double increment, int beams, double max_range,
                          std::vector<double>& out) const {
  const auto n = static_cast<std::size_t>(std::max(beams, 0));
  out.assign(n, max_range);
  if (n == 0) return;
  collectFanFixtures(from, max_range);
  // The beams exactly as rayDistance builds them. A beam's fraction is the minimum over the fixtures
  // it hits, which is what Box2D's clipped ray cast returns whatever the order of the reports.
  const b2Vec2 p1 = toB2(from);
  updateFanDirections(n, first_angle, increment);
  auto beamInput = [&](std::size_t i) {
    b2RayCastInput input;
    input.p1 = p1;
    input.p2 = toB2(from + max_range * fan_dirs_[i]);
    input.maxFraction = 1.0f;
    return input;
  };
  std::vector<b2RayCastInput>& inputs = fan_inputs_;
  inputs.resize(n);
  for (std::size_t i = 0; i < n; ++i) inputs[i] = beamInput(i);
  fan_best_.assign(n, 2.0f);  // > 1: no hit
  auto test = [&](const b2Fixture* f, std::size_t i) {
    b2RayCastOutput hit;
    if (f->RayCast(&hit, inputs[i], 0) && hit.fraction < fan_best_[i]) fan_best_[i] = hit.fraction;
  };
  // Beams whose angle is within `half` of `centre` (with a margin far above rounding): the angle of
  // beam i is first_angle + i * increment, taken modulo 2 pi.
  constexpr double kAngleMargin = 1e-4;  // rad
  auto testWithin = [&](const b2Fixture* f, double centre, double half) {
    half += kAngleMargin;
    if (half >= kPi || increment <= 0.0) {
      for (std::size_t i = 0; i < n; ++i) test(f, i);
      return;
    }
    const double rel = normalizeAngle(centre - first_angle);  // (-pi, pi]
    for (const double shift : {0.0, 2.0 * kPi}) {
      const double lo = std::ceil((rel + shift - half) / increment);
      const double hi = std::floor((rel + shift + half) / increment);
      const double first = std::max(lo, 0.0), last = std::min(hi, static_cast<double>(n - 1));
      for (double k = first; k <= last; k += 1.0) test(f, static_cast<std::size_t>(k));
    }
  };
  for (const b2Fixture* f : fan_fixtures_) {
    if (f->GetBody() == robot_) continue;
    const b2Transform& xf = f->GetBody()->GetTransform();
    const b2Shape* shape = f->GetShape();
    if (shape->GetType() == b2Shape::e_circle) {
      const auto* circle = static_cast<const b2CircleShape*>(shape);
      const Vec2 c = toVec(b2Mul(xf, circle->m_p));
      const double d = (c - from).norm(), r = circle->m_radius + kGridMargin;
      testWithin(f, angleOf(c - from), d > r ? std::asin(r / d) : kPi);
    } else if (shape->GetType() == b2Shape::e_edge) {
      const auto* edge = static_cast<const b2EdgeShape*>(shape);
      const Vec2 a = toVec(b2Mul(xf, edge->m_vertex1)) - from, b = toVec(b2Mul(xf, edge->m_vertex2)) - from;
      // A segment that keeps clear of the sensor subtends less than pi: the arc between its ends.
      if ((closestPointOnSegment(Vec2::Zero(), a, b)).norm() <= kGridMargin) {
        testWithin(f, 0.0, kPi);
      } else {
        const double ta = angleOf(a), span = normalizeAngle(angleOf(b) - ta);
        testWithin(f, ta + span / 2.0, std::abs(span) / 2.0);
      }
    } else {
      testWithin(f, 0.0, kPi);  // polygons: every beam
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (fan_best_[i] <= 1.0f) out[i] = static_cast<double>(fan_best_[i]) * max_range;
}

// Every fixture a beam of the fan can hit overlaps the box the fan reaches: into fan_fixtures_.
void PhysicsWorld::collectFanFixtures(const Vec2& from, double max_range) const {
  fan_fixtures_.clear();
  FixturesInBox query(fan_fixtures_);
  const double reach = max_range + 0.01;
  b2AABB box;
  box.lowerBound = b2Vec2(static_cast<float>(from.x() - reach), static_cast<float>(from.y() - reach));
  box.upperBound = b2Vec2(static_cast<float>(from.x() + reach), static_cast<float>(from.y() + reach));
  world_->QueryAABB(&query, box);
}

// The beam directions into fan_dirs_, unless they are those of the last fan already.
void PhysicsWorld::updateFanDirections(std::size_t n, double first_angle, double increment) const {
  if (fan_dirs_.size() == n && fan_dirs_first_ == first_angle && fan_dirs_increment_ == increment) return;
  fan_dirs_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double angle = first_angle + static_cast<double>(i) * increment;
    fan_dirs_[i] = Vec2(std::cos(angle), std::sin(angle));
  }
  fan_dirs_first_ = first_angle;
  fan_dirs_increment_ = increment;
}

bool PhysicsWorld::lineOfSight(const Vec2& a, const Vec2& b) const {
  if ((b - a).squaredNorm() <= 0.0) return true;
  b2RayCastInput input;
  input.p1 = toB2(a);
  input.p2 = toB2(b);
  input.maxFraction = 1.0f;
  AnyHit cb(static_tree_, static_parts_);
  static_tree_.RayCast(&cb, input);
  return !cb.hit;
}

namespace {
// linesOfSightTo's bins of bearings from the target. Margins are far above rounding; parts close
// to the target go in every bin.
constexpr int kSightBins = 1024;
constexpr double kSightBinWidth = 2.0 * kPi / kSightBins;
constexpr double kSightAngleMargin = 1e-4;  // rad
constexpr double kSightNear = 0.5;          // m

int sightBinOf(double angle) {  // angle in [-pi, pi]
  return std::clamp(static_cast<int>(std::floor((angle + kPi) / kSightBinWidth)), 0, kSightBins - 1);
}
}  // namespace

void PhysicsWorld::linesOfSightTo(const Vec2& target, const std::vector<Vec2>& from, std::vector<char>& visible) const {
  visible.assign(from.size(), 1);
  if (from.empty() || static_parts_.empty()) return;
  double reach = 0.0;
  for (const Vec2& p : from) reach = std::max(reach, (p - target).norm());
  reach += 0.01;
  collectSightParts(target, reach);
  // Few segments, or few among much geometry: one tree walk each (building the bins below costs
  // about as much as 30 walks, too much for a few people: docs/performance.md, "Crowds").
  constexpr std::size_t kMinSegmentsForBins = 32;
  if (from.size() < kMinSegmentsForBins || sight_parts_.size() > 4 * from.size()) {
    for (std::size_t i = 0; i < from.size(); ++i) visible[i] = lineOfSight(from[i], target) ? 1 : 0;
    return;
  }
  binSightParts(target);
  testSightsInBins(target, from, visible);
}

// The static parts the segments within `reach` of the target can cross, into sight_parts_.
void PhysicsWorld::collectSightParts(const Vec2& target, double reach) const {
  sight_parts_.clear();
  b2AABB box;
  box.lowerBound = b2Vec2(static_cast<float>(target.x() - reach), static_cast<float>(target.y() - reach));
  box.upperBound = b2Vec2(static_cast<float>(target.x() + reach), static_cast<float>(target.y() + reach));
  PartsInBox query(static_tree_, sight_parts_);
  static_tree_.Query(&query, box);
}

// Bins sight_parts_ by their bearing from the target (compressed rows: sight_start_, sight_sorted_).
// A part that blocks the segment from p to the target holds a point of it, which has p's bearing and
// is not farther than p: the bin of p's bearing lists the part, with its least distance to the target.
void PhysicsWorld::binSightParts(const Vec2& target) const {
  sight_entries_.clear();
  auto add = [&](std::uint32_t part, double distance, double centre, double half) {
    const auto d = static_cast<float>(std::max(0.0, distance - kGridMargin));
    if (distance < kSightNear || half + kSightAngleMargin >= kPi) {
      for (int b = 0; b < kSightBins; ++b) sight_entries_.push_back({static_cast<std::uint32_t>(b), part, d});
      return;
    }
    const double lo = normalizeAngle(centre - half - kSightAngleMargin);
    const int first = sightBinOf(lo),
              count = static_cast<int>(std::ceil((2.0 * (half + kSightAngleMargin)) / kSightBinWidth)) + 1;
    for (int k = 0; k <= count && k < kSightBins; ++k)
      sight_entries_.push_back({static_cast<std::uint32_t>((first + k) % kSightBins), part, d});
  };
  for (const std::uint32_t part : sight_parts_) {
    const b2Fixture* f = static_parts_[part].fixture;
    const b2Transform& xf = f->GetBody()->GetTransform();
    const b2Shape* shape = f->GetShape();
    if (shape->GetType() == b2Shape::e_circle) {
      const auto* circle = static_cast<const b2CircleShape*>(shape);
      const Vec2 c = toVec(b2Mul(xf, circle->m_p)) - target;
      const double r = circle->m_radius + kGridMargin, d = c.norm();
      add(part, d - r, angleOf(c), d > r ? std::asin(r / d) : kPi);
    } else {
      const auto* edge = static_cast<const b2EdgeShape*>(shape);
      const Vec2 a = toVec(b2Mul(xf, edge->m_vertex1)) - target, b = toVec(b2Mul(xf, edge->m_vertex2)) - target;
      const double ta = angleOf(a), span = normalizeAngle(angleOf(b) - ta);
      add(part, closestPointOnSegment(Vec2::Zero(), a, b).norm(), ta + span / 2.0, std::abs(span) / 2.0);
    }
  }
  sight_start_.assign(kSightBins + 1, 0);
  for (const SightEntry& e : sight_entries_) ++sight_start_[e.bin + 1];
  for (int b = 1; b <= kSightBins; ++b)
    sight_start_[static_cast<std::size_t>(b)] += sight_start_[static_cast<std::size_t>(b - 1)];
  sight_sorted_.resize(sight_entries_.size());
  std::vector<std::uint32_t>& fill = sight_fill_;
  fill.assign(sight_start_.begin(), sight_start_.end() - 1);
  for (const SightEntry& e : sight_entries_) sight_sorted_[fill[e.bin]++] = e;
}

// visible[i] = 0 for each segment from[i]-target a part in its bin blocks (lineOfSight's ray).
void PhysicsWorld::testSightsInBins(const Vec2& target, const std::vector<Vec2>& from,
                                    std::vector<char>& visible) const {
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Vec2 v = from[i] - target;
    const double dist = v.norm();
    if (dist <= 0.0) continue;
    b2RayCastInput input;  // exactly lineOfSight's ray
    input.p1 = toB2(from[i]);
    input.p2 = toB2(target);
    input.maxFraction = 1.0f;
    const int b = sightBinOf(angleOf(v));
    for (std::uint32_t k = sight_start_[static_cast<std::size_t>(b)]; k < sight_start_[static_cast<std::size_t>(b) + 1];
         ++k) {
      const SightEntry& e = sight_sorted_[k];
      if (e.distance > dist + kGridMargin) continue;
      b2RayCastOutput out;
      if (static_parts_[e.part].fixture->RayCast(&out, input, 0)) {
        visible[i] = 0;
        break;
      }
    }
  }
}

void PhysicsWorld::closestObstaclePoints(const Vec2& p, double radius, std::vector<Vec2>& out) const {
  out.clear();
  int ix, iy;
  if (radius <= grid_.radius && grid_.nx > 0 && grid_.cellOf(p, ix, iy)) {
    // The cell lists, in shape order, every shape that can be within the grid's radius of p.
    const std::size_t c =
        static_cast<std::size_t>(iy) * static_cast<std::size_t>(grid_.nx) + static_cast<std::size_t>(ix);
    for (std::uint32_t k = grid_.shape_start[c]; k < grid_.shape_start[c + 1]; ++k) {
      const Vec2 q = scenario_.shapes[grid_.shapes[k]].closestPoint(p);
      if ((q - p).squaredNorm() <= radius * radius) out.push_back(q);
    }
    return;
  }
  if (grid_.nx > 0 && radius <= grid_.radius) return;  // outside the grid: nothing within the radius
  candidate_shapes_.clear();
  b2AABB box;
  box.lowerBound = b2Vec2(static_cast<float>(p.x() - radius), static_cast<float>(p.y() - radius));
  box.upperBound = b2Vec2(static_cast<float>(p.x() + radius), static_cast<float>(p.y() + radius));
  ShapesInBox cb(static_tree_, static_parts_, candidate_shapes_);
  static_tree_.Query(&cb, box);
  // A shape within the radius has a fixture within the box; the exact test is the shape's own.
  std::sort(candidate_shapes_.begin(), candidate_shapes_.end());
  candidate_shapes_.erase(std::unique(candidate_shapes_.begin(), candidate_shapes_.end()), candidate_shapes_.end());
  for (const int i : candidate_shapes_) {
    const Vec2 c = scenario_.shapes[static_cast<std::size_t>(i)].closestPoint(p);
    if ((c - p).squaredNorm() <= radius * radius) out.push_back(c);
  }
}

bool PhysicsWorld::closestObstaclePoint(const Vec2& p, double radius, Vec2& out) const {
  int ix, iy;
  if (!(radius <= grid_.radius && grid_.nx > 0 && grid_.cellOf(p, ix, iy))) {
    std::vector<Vec2> points;  // off the grid: the general query
    closestObstaclePoints(p, radius, points);
    bool found = false;
    double best = 0.0;
    for (const Vec2& q : points)
      if (!found || (q - p).squaredNorm() < best) {
        best = (q - p).squaredNorm();
        out = q;
        found = true;
      }
    return found;
  }
  const std::size_t c =
      static_cast<std::size_t>(iy) * static_cast<std::size_t>(grid_.nx) + static_cast<std::size_t>(ix);
  bool found = false;
  double best = radius * radius;
  for (std::uint32_t k = grid_.shape_start[c]; k < grid_.shape_start[c + 1]; ++k) {
    const auto& b = shape_bounds_[grid_.shapes[k]];
    const double dx = std::max({0.0, b[0] - p.x(), p.x() - b[2]}), dy = std::max({0.0, b[1] - p.y(), p.y() - b[3]});
    // A shape is never closer than its bounds: skip it when they are no closer than the best.
    if (dx * dx + dy * dy > best || (found && dx * dx + dy * dy >= best)) continue;
    const Vec2 q = scenario_.shapes[grid_.shapes[k]].closestPoint(p);
    const double d2 = (q - p).squaredNorm();
    if (found ? d2 < best : d2 <= best) {
      best = d2;
      out = q;
      found = true;
    }
  }
  return found;
}

std::vector<Vec2> PhysicsWorld::closestObstaclePoints(const Vec2& p, double radius) const {
  std::vector<Vec2> points;
  closestObstaclePoints(p, radius, points);
  return points;
}

}  // namespace hunav::worldsim

// Box2D 2.4 times every step and every island of it for its b2Profile with gettimeofday (about five
// calls per island, and each person is an island of its own: docs/performance.md, "Crowds").
// Nothing here reads b2Profile, and the simulation must not read the wall clock: these
// definitions of b2Timer's members take the place of libbox2d's (ELF symbol interposition: the
// library calls them through its PLT) and make the timers free. b2Profile then reads 0.
b2Timer::b2Timer() : m_start_sec(0), m_start_usec(0) {}
void b2Timer::Reset() {}
float b2Timer::GetMilliseconds() const { return 0.0f; }
