// HuNavSim 2.0's node library (manager/README.md, "The node library"): the nodes
// beyond HuNavSim 1's. Each node moves only the person whose tree it is (the original's group and
// conversation nodes move every member from the main person's tree; here every member runs the node
// in its own tree, and all of them compute the same formation from the same snapshot). Durations count
// simulation time: the original counts its steady clock, so a run's result depended on the machine's
// speed; here the same scenario and seed give the same trajectories in every mode.
#include "bt_social.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace hunav::manager {

namespace {

using Kind = NodeLibrary::Kind;

// Within this distance of its slot a conversation member counts as arrived (m); the circle starts
// talking when every member is within kCircleFormed of its slot.
constexpr double kSlotReached = 0.15;
constexpr double kCircleFormed = 0.3;
// Each member of a conversation speaks in turn for this long (s of simulation time).
constexpr double kConversationTurn = 3.0;
// Facing a target within this angle ends a look (rad).
constexpr double kFacing = 1e-3;
// A blocker is in place within this distance of its spot in front of the target (m); it runs there
// at up to kBlockSpeed, slowing down as it arrives (HuNavSim 2: 2.5 m/s, goal radius 0.2).
constexpr double kBlockInPlace = 0.2;
constexpr double kBlockSpeed = 2.5;
// A leader moving slower than this is "standing": its heading, not its velocity, says where behind is.
constexpr double kMovingSpeed = 0.1;

Vec2 posOf(const agent_state_t& a) { return Vec2(a.x, a.y); }
Vec2 here(const TickContext& c) { return posOf(c.in); }
std::int64_t now(const TickContext& c) { return c.snap.request->utime; }
std::int64_t usOf(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e6)); }

// Writes an output port's value: to the blackboard for the nodes after it this tick, and to the
// person's memory, from which the next tick's blackboard starts.
void setOutput(TickContext& c, BbKey key, int value) {
  c.bb[static_cast<std::size_t>(key)] = value;
  c.memory.outputs[static_cast<std::size_t>(static_cast<int>(key) - kFirstOutputKey)] = value;
}

// The person (or the robot) with this id at time t; nullptr when there is none.
const agent_state_t* stateOf(const TickContext& c, int id) {
  if (id == c.snap.request->robot.id) return c.snap.robotState();
  const int i = c.snap.indexOf(id);
  return i < 0 ? nullptr : &c.snap.request->agents[static_cast<std::size_t>(i)];
}

// Stands, turning toward `target` at kTurnRate.
void standFacing(TickContext& c, const Vec2& target) {
  standStill(c);
  turnToward(c, target, kTurnRate * c.dt);
}

// Turns toward `target` at kTurnRate; a person not yet moved this tick stands while it turns.
// Returns whether it now faces the target.
bool lookAt(TickContext& c, const Vec2& target) {
  if (!c.memory.moved) standStill(c);
  turnToward(c, target, kTurnRate * c.dt);
  const Vec2 d = target - Vec2(c.out.x, c.out.y);
  return d.squaredNorm() == 0.0 || std::abs(normalizeAngle(angleOf(d) - c.out.yaw)) <= kFacing;
}

// Walks on toward the current goal (robot as a person) and takes the next goal when there: what a
// person does while it waits for someone to speak or look (HuNavSim 2 does the same).
void walkOn(TickContext& c) {
  if (c.memory.moved) return;
  if (!c.out.goals.empty()) {
    const point2d_t& g = c.out.goals.front();
    if (std::hypot(g.x - c.in.x, g.y - c.in.y) <= c.in.goal_radius + kGoalSwitchMargin) {
      const point2d_t reached = g;
      c.out.goals.erase(c.out.goals.begin());
      if (c.out.cyclic_goals) c.out.goals.push_back(reached);
      c.out.num_goals = static_cast<int32_t>(c.out.goals.size());
    }
  }
  regularMove(c, RobotAs::Person);
}

PortSpec num(const std::string& name, const std::string& def) {
  return PortSpec{name, PortType::Number, false, def, {}, BbKey::TargetAgentId};
}
PortSpec req(const std::string& name) { return PortSpec{name, PortType::Number, true, "", {}, BbKey::TargetAgentId}; }
PortSpec out(const std::string& name, BbKey key) {
  return PortSpec{name, PortType::Output, false, "{" + name + "}", {}, key};
}
PortSpec text(const std::string& name, const std::string& def) {
  return PortSpec{name, PortType::String, false, def, {}, BbKey::TargetAgentId};
}
PortSpec ids(const std::string& name) { return PortSpec{name, PortType::IdList, true, "", {}, BbKey::TargetAgentId}; }

// A point given by goal_id (HuNavSim 2's global goals) or by x and y: one of the two is required.
std::string pointCheck(const std::vector<PortSpec>& specs, const std::vector<PortValue>& v, const std::string& id,
                       const std::string& x, const std::string& y) {
  auto at = [&](const std::string& n) -> const PortValue& {
    for (std::size_t i = 0; i < specs.size(); ++i)
      if (specs[i].name == n) return v[i];
    return v.front();
  };
  const bool has_id = at(id).given, has_x = at(x).given, has_y = at(y).given;
  if (has_id && (has_x || has_y)) return "give " + id + " or " + x + " and " + y + ", not both";
  if (has_x && !has_y) return "missing port '" + y + "'";
  if (has_y && !has_x) return "missing port '" + x + "'";
  if (!has_id && !has_x) return "missing port '" + id + "' (or " + x + " and " + y + ")";
  return "";
}

// ---------------------------------------------------------------------------------------------------
// Base classes

// A node of this library: a BtNode that may read a point given by goal_id (HuNavSim 2's global
// goals) or by x and y.
class SocialNode : public BtNode {
 public:
  // The point of the goal_id / x / y ports first, first + 1, first + 2; false when goal_id names no
  // global goal (a manager without the scenario).
  bool pointAt(const TickContext& c, std::size_t first, Vec2& p) const {
    if (!port(first).given) {
      p = Vec2(number(first + 1, c), number(first + 2, c));
      return true;
    }
    if (c.snap.global_goals == nullptr) return false;
    const auto it = c.snap.global_goals->find(static_cast<int>(number(first, c)));
    if (it == c.snap.global_goals->end()) return false;
    p = it->second;
    return true;
  }
};

// A node that may run over several ticks: it starts when ticked while not running, and measures
// the simulation time since then, the current tick's step included (so a 3 s wait at dt 0.01 holds
// for exactly 300 ticks).
class TimedNode : public SocialNode {
 protected:
  Status onTick(TickContext& c) override {
    if (!running()) {
      start_ = now(c);
      onStart(c);
    }
    return onRunning(c);
  }
  virtual void onStart(TickContext&) {}
  virtual Status onRunning(TickContext& c) = 0;
  std::int64_t elapsedUs(const TickContext& c) const { return now(c) - start_ + usOf(c.dt); }
  std::int64_t startUs() const { return start_; }
  // duration <= 0: never.
  bool expired(const TickContext& c, double duration) const { return duration > 0.0 && elapsedUs(c) >= usOf(duration); }
  // The end of a stateful action's tick: it shows as active, RUNNING until `duration` s have passed.
  Status activeFor(TickContext& c, double duration) const {
    c.out.behavior_state = agent_state_t::STATE_ACTIVE_1;
    return expired(c, duration) ? Status::Success : Status::Running;
  }

 private:
  std::int64_t start_ = 0;
};

// Most stateful nodes come in two variants (IsAnyoneSpeaking / IsSpeaking, ApproachRobot /
// ApproachAgent, ...): one about anyone or the robot, with no port for it, and one about the person
// named by its first port. The ports after that are the same in both, read with arg(i).
enum class TargetPort { None, First };
class TargetedNode : public TimedNode {
 public:
  explicit TargetedNode(TargetPort target) : named_(target == TargetPort::First) {}

 protected:
  bool named() const { return named_; }
  int targetId(const TickContext& c) const { return static_cast<int>(number(0, c)); }
  double arg(std::size_t i, const TickContext& c) const { return number(named_ ? i + 1 : i, c); }
  // The named person, or the robot; nullptr when absent or when it is this person.
  const agent_state_t* target(const TickContext& c) const {
    const agent_state_t* t = named_ ? stateOf(c, targetId(c)) : c.snap.robotState();
    return t == nullptr || t->id == c.in.id ? nullptr : t;
  }

  // The end of a condition's tick: SUCCESS when someone was found (IsAnyone... writes who to its
  // output `key`); FAILURE when the time is up; otherwise it walks on, RUNNING.
  Status awaited(TickContext& c, int found, BbKey key, double duration) {
    if (found >= 0) {
      if (!named_) setOutput(c, key, found);
      return Status::Success;
    }
    if (expired(c, duration) || duration <= 0.0) return Status::Failure;
    walkOn(c);
    return Status::Running;
  }

 private:
  bool named_;
};

// A stateful action about its target: FAILURE when the target is absent (or is this person);
// otherwise it acts, shown as active, RUNNING until the `duration` port's time has passed (then
// SUCCESS; for ever when <= 0).
class TargetedAction : public TargetedNode {
 public:
  TargetedAction(TargetPort target, std::size_t duration_arg) : TargetedNode(target), duration_arg_(duration_arg) {}

 protected:
  Status onRunning(TickContext& c) final {
    const agent_state_t* t = target(c);
    if (t == nullptr) return Status::Failure;
    act(c, *t);
    return activeFor(c, arg(duration_arg_, c));
  }
  virtual void act(TickContext& c, const agent_state_t& target) = 0;

 private:
  std::size_t duration_arg_;
};

// A leaf defined by a lambda (SUCCESS or FAILURE in one tick).
template <class F>
class Leaf : public SocialNode {
 public:
  explicit Leaf(F f) : f_(std::move(f)) {}
  double value(std::size_t i, const TickContext& c) const { return number(i, c); }
  const PortValue& portValue(std::size_t i) const { return port(i); }

 protected:
  Status onTick(TickContext& c) override { return f_(*this, c) ? Status::Success : Status::Failure; }

 private:
  F f_;
};

template <class F>
void addLeaf(NodeLibrary& lib, const std::string& name, std::vector<PortSpec> ports, F f) {
  lib.addNode<Leaf<F>>(name, Kind::Leaf, std::move(ports), f);
}

// ---------------------------------------------------------------------------------------------------
// Stateful conditions: listen (or watch) for up to `duration` s while walking on; SUCCESS as soon
// as the awaited person speaks (looks) within distance_threshold, FAILURE when the time is up.

// IsAnyoneSpeaking(distance_threshold, duration, speaker_id) / IsSpeaking(target_id, ...).
class SpeakingCondition : public TargetedNode {
 public:
  using TargetedNode::TargetedNode;

 protected:
  Status onRunning(TickContext& c) override {
    const double range = arg(0, c), duration = arg(1, c);
    int found = -1;
    double best = std::numeric_limits<double>::infinity();
    if (c.snap.social != nullptr) {
      for (const PersonSocial& p : *c.snap.social) {
        if (p.id == c.in.id || !p.speaking(now(c))) continue;
        if (named() && p.id != targetId(c)) continue;
        const agent_state_t* s = stateOf(c, p.id);
        if (s == nullptr) continue;
        const double d = (posOf(*s) - here(c)).norm();
        if (d <= range && d < best) best = d, found = p.id;  // the nearest speaker
      }
    }
    return awaited(c, found, BbKey::SpeakerId, duration);
  }
};

// Whether `watcher` (a person or the robot) within `range` looks at p: the bearing of p from its
// heading is within `angle`.
bool looksAt(const agent_state_t& watcher, const Vec2& p, double range, double angle) {
  const Vec2 d = p - posOf(watcher);
  if (d.squaredNorm() > range * range || d.squaredNorm() == 0.0) return false;
  return std::abs(normalizeAngle(angleOf(d) - watcher.yaw)) < angle;
}

// IsAnyoneLookingAtMe(distance_threshold, angle_threshold, duration, observer_id) /
// IsLookingAtMe(target_id, ...): geometry of time t (people and the robot), nearest watcher first.
class LookingCondition : public TargetedNode {
 public:
  using TargetedNode::TargetedNode;

 protected:
  Status onRunning(TickContext& c) override {
    const double range = arg(0, c), angle = arg(1, c), duration = arg(2, c);
    int found = -1;
    if (!named()) {
      double best = std::numeric_limits<double>::infinity();
      auto consider = [&](const agent_state_t& w) {
        if (w.id == c.in.id || !looksAt(w, here(c), range, angle)) return;
        const double d = (posOf(w) - here(c)).norm();
        if (d < best || (d == best && w.id < found)) best = d, found = w.id;
      };
      for (int j : c.snap.by_id) consider(c.snap.request->agents[static_cast<std::size_t>(j)]);
      if (const agent_state_t* robot = c.snap.robotState()) consider(*robot);
    } else {
      const agent_state_t* w = target(c);
      if (w != nullptr && looksAt(*w, here(c), range, angle)) found = w->id;
    }
    return awaited(c, found, BbKey::ObserverId, duration);
  }
};

// ---------------------------------------------------------------------------------------------------
// Stateful actions: RUNNING until `duration` s have passed (SUCCESS then), for ever when <= 0.

// StopAndWaitTimerAction(wait_duration): stands still for wait_duration s (wait_duration / dt ticks),
// then SUCCESS on the next tick without moving, so that the next node acts in it.
class StopAndWait : public TimedNode {
 protected:
  Status onRunning(TickContext& c) override {
    if (now(c) - startUs() >= usOf(number(0, c))) return Status::Success;
    standStill(c);
    return Status::Running;
  }
};

// ApproachRobot(closest_dist, max_vel, duration) / ApproachAgent(target_agent_id, closest_dist,
// max_vel, duration): walks up to the target at max_vel*d/(d + closest_dist) (HuNavSim 2's curious
// approach; slower as it comes near), stops within closest_dist and turns to face it. The robot is
// left out of the approacher's social force (it walks up to it on purpose); a person target pushes
// as any person does.
class Approach : public TargetedAction {
 public:
  explicit Approach(TargetPort target) : TargetedAction(target, 2) {}

 protected:
  void act(TickContext& c, const agent_state_t& t) override {
    const double stop = arg(0, c), vel = arg(1, c);
    const Vec2 target = posOf(t);
    const double d = (target - here(c)).norm();
    if (d <= stop) {
      standFacing(c, target);
    } else {
      sfmMove(c, named() ? RobotAs::Person : RobotAs::Ignored, vel * d / (d + stop), &target, Vec2::Zero(), t.radius);
    }
  }
};

// BlockRobot(front_dist, duration) / BlockAgent(target_agent_id, front_dist, duration): stands in
// the target's way, front_dist ahead of it along its heading (HuNavSim 2: 1.5 m when front_dist
// <= 0.5); runs there at up to 2.5 m/s, slowing as it arrives, and once in place stands facing it.
class Block : public TargetedAction {
 public:
  explicit Block(TargetPort target) : TargetedAction(target, 1) {}

 protected:
  void act(TickContext& c, const agent_state_t& t) override {
    double front = arg(0, c);
    if (front <= 0.5) front = 1.5;
    const Vec2 target = posOf(t);
    const Vec2 spot = target + front * Vec2(std::cos(t.yaw), std::sin(t.yaw));
    const double e = (spot - here(c)).norm();
    if (e <= kBlockInPlace) {
      standFacing(c, target);
    } else {
      // The target is left out of the blocker's social force: it wants to be in its way.
      sfmMove(c, named() ? RobotAs::Person : RobotAs::Ignored, std::min(kBlockSpeed, 2.0 * e), &spot, Vec2::Zero(),
              0.0);
    }
  }
};

// AvoidRobot(safe_distance, runaway_vel, duration): HuNavSim 2's later scared person: within
// safe_distance of the robot it walks away at runaway_vel to the point safe_distance from the robot
// on its own side; from there it stands and watches the robot.
class AvoidRobot : public TimedNode {
 protected:
  Status onRunning(TickContext& c) override {
    if (c.snap.robot_absent) return Status::Failure;
    const double safe = number(0, c), vel = number(1, c), duration = number(2, c);
    const Vec2 r(c.snap.request->robot.x, c.snap.request->robot.y);
    Vec2 away = here(c) - r;
    const double d = away.norm();
    if (d >= safe) {
      standFacing(c, r);
    } else {
      away = d > 0.0 ? Vec2(away / d) : Vec2(-std::cos(c.in.yaw), -std::sin(c.in.yaw));
      const Vec2 spot = r + safe * away;
      sfmMove(c, RobotAs::Ignored, vel, &spot, Vec2::Zero(), 0.3);
    }
    return activeFor(c, duration);
  }
};

// FollowAgent(target_agent_id, closest_dist, max_vel, duration): keeps closest_dist behind the
// leader: heads for the point closest_dist behind it (along its velocity, or its heading when it
// stands) at the leader's speed plus the gap to that point per second, at most max_vel. So it
// catches up when left behind, walks at the leader's pace on the spot, and stops when the leader
// stops. (HuNavSim 2 walks at the leader itself and scales its speed by (d/closest_dist)^2 inside
// closest_dist, which lets the follower keep less than closest_dist.)
class FollowAgent : public TargetedAction {
 public:
  FollowAgent() : TargetedAction(TargetPort::First, 2) {}

 protected:
  void act(TickContext& c, const agent_state_t& l) override {
    const double gap = arg(0, c), max_vel = arg(1, c);
    const Vec2 lv(l.vx, l.vy);
    const double speed = lv.norm();
    const Vec2 dir = speed > kMovingSpeed ? Vec2(lv / speed) : Vec2(std::cos(l.yaw), std::sin(l.yaw));
    const Vec2 spot = posOf(l) - gap * dir;
    const double e = (spot - here(c)).norm();
    sfmMove(c, l.type == agent_state_t::TYPE_ROBOT ? RobotAs::Ignored : RobotAs::Person,
            std::clamp(speed + e, 0.0, max_vel), &spot, Vec2::Zero(), 0.0);
  }
};

// The position of this person in [main, non_main...], or -1.
int memberIndex(int id, int main_id, const std::vector<int>& others) {
  if (id == main_id) return 0;
  const auto it = std::find(others.begin(), others.end(), id);
  return it == others.end() ? -1 : static_cast<int>(it - others.begin()) + 1;
}

// SetGroupWalk(main_agent_id, non_main_agent_ids, duration): the members walk as one group (group
// id = main_agent_id, from the next step: the group forces keep them together); the main person
// walks its own goals, the others head for the main person's current goal. When the time is up (or
// the node is halted) everyone returns to the group it had.
class GroupWalk : public TimedNode {
 public:
  void halt() override {
    if (memory_ != nullptr) memory_->group_override = -2;
    TimedNode::halt();
  }

 protected:
  Status onRunning(TickContext& c) override {
    memory_ = &c.memory;
    const int main_id = static_cast<int>(number(0, c));
    const int k = memberIndex(c.in.id, main_id, port(1).ids);
    const agent_state_t* main = stateOf(c, main_id);
    if (k < 0 || main == nullptr) return Status::Failure;
    if (expired(c, number(2, c))) {
      c.memory.group_override = -2;
      walkOn(c);
      return Status::Success;
    }
    c.memory.group_override = main_id;
    if (k == 0 || main->goals.empty()) {
      walkOn(c);
    } else {
      const Vec2 g(main->goals.front().x, main->goals.front().y);
      sfmMove(c, RobotAs::Person, c.in.desired_speed, &g, Vec2::Zero(), main->goal_radius);
    }
    return Status::Running;
  }

 private:
  AgentMemory* memory_ = nullptr;
};

// ConversationFormation(main_agent_id, non_main_agent_ids, conversation_duration, goal_id | center_x
// center_y, radius, start_angle): the members stand on a circle about the centre, member k (main
// first, then non_main_agent_ids in order) at start_angle + 2 pi k / N, radius 0.5 + 0.2 (N - 1)
// unless given (HuNavSim 2's); each walks to its place, then stands facing the centre. When every
// member is in place the conversation starts: they speak in turn, kConversationTurn s each, for
// conversation_duration s (<= 0: for ever), then SUCCESS.
class ConversationFormation : public TimedNode {
 protected:
  void onStart(TickContext&) override { talking_ = false; }
  Status onRunning(TickContext& c) override {
    const int main_id = static_cast<int>(number(0, c));
    const std::vector<int>& others = port(1).ids;
    const int k = memberIndex(c.in.id, main_id, others);
    Vec2 centre;
    if (k < 0 || !pointAt(c, 3, centre)) return Status::Failure;
    const int n = static_cast<int>(others.size()) + 1;
    const double radius = number(6, c) > 0.0 ? number(6, c) : 0.5 + 0.2 * static_cast<double>(n - 1);
    auto slot = [&](int i) {
      const double a = number(7, c) + 2.0 * kPi * i / n;
      return Vec2(centre + radius * Vec2(std::cos(a), std::sin(a)));
    };
    c.memory.social.conversation = main_id;
    const Vec2 mine = slot(k);
    if ((mine - here(c)).norm() > kSlotReached) {
      sfmMove(c, RobotAs::Person, c.in.desired_speed, &mine, Vec2::Zero(), 0.0);
    } else {
      standFacing(c, centre);
    }
    if (!talking_) {  // every member in place at time t: the same tick for all of them
      bool formed = true;
      for (int i = 0; i < n && formed; ++i) {
        const agent_state_t* m = stateOf(c, i == 0 ? main_id : others[static_cast<std::size_t>(i - 1)]);
        formed = m != nullptr && (posOf(*m) - slot(i)).norm() <= kCircleFormed;
      }
      if (formed) {
        talking_ = true;
        talk_start_ = now(c);
      }
    }
    if (!talking_) return Status::Running;
    const std::int64_t talked = now(c) - talk_start_;
    if (static_cast<int>((talked / usOf(kConversationTurn)) % n) == k) {
      // through the reply's time (t + dt), when the others hear it
      c.memory.social.speaking_until = now(c) + usOf(c.dt) + 1;
      c.memory.social.message = "(talking in the circle of " + std::to_string(main_id) + ")";
    }
    const double duration = number(2, c);
    return duration > 0.0 && talked + usOf(c.dt) >= usOf(duration) ? Status::Success : Status::Running;
  }

 private:
  bool talking_ = false;
  std::int64_t talk_start_ = 0;
};

// GoTo(goal_id | x y, tolerance): walks to the point (routes, social forces, robot as a person);
// SUCCESS once within tolerance (standing there that tick).
class GoTo : public SocialNode {
 protected:
  Status onTick(TickContext& c) override {
    Vec2 g;
    if (!pointAt(c, 0, g)) return Status::Failure;
    if ((g - here(c)).norm() <= number(3, c)) {
      standStill(c);
      return Status::Success;
    }
    sfmMove(c, RobotAs::Person, c.in.desired_speed, &g, Vec2::Zero(), 0.0);
    return Status::Running;
  }
};

// SetGoal(goal_id | x y): makes the point the current goal (put in front of the queue unless already
// there; HuNavSim 2 appends it with radius 0.1: here it is the goal now, with the person's radius).
class SetGoalNode : public SocialNode {
 protected:
  Status onTick(TickContext& c) override {
    Vec2 p;
    if (!pointAt(c, 0, p)) return Status::Failure;
    const point2d_t g{p.x(), p.y()};
    if (c.out.goals.empty() || c.out.goals.front().x != g.x || c.out.goals.front().y != g.y) {
      c.out.goals.insert(c.out.goals.begin(), g);
      c.out.num_goals = static_cast<int32_t>(c.out.goals.size());
    }
    return Status::Success;
  }
};

// LookAtAgent(observer_id, target_id) / LookAtRobot / LookAtPoint(goal_id | x y): turns toward
// the target at pi rad/s, standing unless a motion node already moved the person this tick (then it
// looks while it walks); SUCCESS once it faces the target, RUNNING while it turns.
enum class LookTarget { Agent, Robot, Point };
class LookAt : public SocialNode {
 public:
  explicit LookAt(LookTarget what) : what_(what) {}

 protected:
  Status onTick(TickContext& c) override {
    Vec2 target;
    int id = -1;
    if (what_ == LookTarget::Point) {
      if (!pointAt(c, 0, target)) return Status::Failure;
    } else {
      const agent_state_t* t =
          what_ == LookTarget::Robot ? c.snap.robotState() : stateOf(c, static_cast<int>(number(1, c)));
      if (t == nullptr || t->id == c.in.id) return Status::Failure;
      target = posOf(*t);
      id = t->id;
    }
    c.memory.social.looking_at = id;
    return lookAt(c, target) ? Status::Success : Status::Running;
  }

 private:
  LookTarget what_;
};

// TimeDelay(delay): FAILURE without ticking the child until `delay` s of simulation time have passed
// since its first tick (or its last halt); then the child's status.
class TimeDelay : public BtNode {
 public:
  void halt() override {
    started_ = false;
    haltChildren();
    BtNode::halt();
  }

 protected:
  Status onTick(TickContext& c) override {
    if (!started_) {
      started_ = true;
      start_ = now(c);
    }
    if (now(c) - start_ + usOf(c.dt) < usOf(number(0, c))) return Status::Failure;
    const Status s = child(0).tick(c);
    if (s != Status::Running) started_ = false;  // the next use waits again
    return s;
  }

 private:
  bool started_ = false;
  std::int64_t start_ = 0;
};

template <class T, class... Args>
void addStateful(NodeLibrary& lib, const std::string& name, std::vector<PortSpec> ports, Args... args) {
  lib.addNode<T>(name, Kind::Leaf, std::move(ports), args...);
}

void markSocial(NodeLibrary& lib, const std::string& name) { lib.findMutable(name)->social = true; }

void setPointCheck(NodeLibrary& lib, const std::string& name, const std::string& id, const std::string& x,
                   const std::string& y) {
  lib.findMutable(name)->check = [id, x, y](const std::vector<PortSpec>& s, const std::vector<PortValue>& v) {
    return pointCheck(s, v, id, x, y);
  };
}

// observer_id of LookAtAgent: the person whose tree it is (a node moves only its own person).
std::string observerIsSelf(const std::vector<PortSpec>&, const std::vector<PortValue>& v) {
  if (v[0].from_blackboard && v[0].key == BbKey::Id) return "";
  return "port observer_id: '" + v[0].text +
         "' is not this agent's id: a node turns only the person whose tree it is; write "
         "observer_id=\"{id}\" or leave the port out";
}

}  // namespace

void registerSocialNodes(NodeLibrary& lib) {
  const std::string fov = std::to_string(kHalfFieldOfView);
  // --- conditions
  addLeaf(lib, "IsAgentVisible",
          {num("observer_id", "{id}"), req("agent_id"), num("distance", "5.0"), num("field_of_view", fov)},
          [](auto& n, TickContext& c) {
            const agent_state_t* o = stateOf(c, static_cast<int>(n.value(0, c)));
            const agent_state_t* t = stateOf(c, static_cast<int>(n.value(1, c)));
            if (o == nullptr || t == nullptr || o == t) return false;
            const Vec2 d = posOf(*t) - posOf(*o);
            const double range = n.value(2, c);
            return d.squaredNorm() <= range * range && std::abs(normalizeAngle(angleOf(d) - o->yaw)) <= n.value(3, c);
          });
  addLeaf(lib, "IsAgentClose", {num("observer_id", "{id}"), req("target_agent_id"), num("threshold", "1.0")},
          [](auto& n, TickContext& c) {
            const agent_state_t* o = stateOf(c, static_cast<int>(n.value(0, c)));
            const agent_state_t* t = stateOf(c, static_cast<int>(n.value(1, c)));
            return o != nullptr && t != nullptr && o != t && (posOf(*t) - posOf(*o)).norm() < n.value(2, c);
          });
  addLeaf(lib, "IsAtPosition",
          {num("goal_id", "-1"), num("target_x", "1.0"), num("target_y", "1.0"), num("tolerance", "0.1")},
          [](auto& n, TickContext& c) {
            Vec2 g;
            if (!n.pointAt(c, 0, g)) return false;
            return (g - here(c)).norm() <= n.value(3, c);
          });
  addStateful<SpeakingCondition>(
      lib, "IsAnyoneSpeaking",
      {num("distance_threshold", "5.0"), num("duration", "5.0"), out("speaker_id", BbKey::SpeakerId)},
      TargetPort::None);
  addStateful<SpeakingCondition>(lib, "IsSpeaking",
                                 {req("target_id"), num("distance_threshold", "5.0"), num("duration", "5.0")},
                                 TargetPort::First);
  addStateful<LookingCondition>(lib, "IsAnyoneLookingAtMe",
                                {num("distance_threshold", "5.0"), num("angle_threshold", "0.2"),
                                 num("duration", "5.0"), out("observer_id", BbKey::ObserverId)},
                                TargetPort::None);
  addStateful<LookingCondition>(
      lib, "IsLookingAtMe",
      {req("target_id"), num("distance_threshold", "5.0"), num("angle_threshold", "0.2"), num("duration", "5.0")},
      TargetPort::First);

  // --- simple actions
  addLeaf(lib, "FindNearestAgent", {out("target_agent_id", BbKey::TargetAgentId)}, [](auto&, TickContext& c) {
    int found = -1;
    double best = std::numeric_limits<double>::infinity();
    for (int j : c.snap.by_id) {  // id order: the lowest id wins a tie
      const agent_state_t& o = c.snap.request->agents[static_cast<std::size_t>(j)];
      if (o.id == c.in.id) continue;
      const double d = (posOf(o) - here(c)).norm();
      if (d < best) best = d, found = o.id;
    }
    if (found < 0) return false;
    setOutput(c, BbKey::TargetAgentId, found);
    return true;
  });
  addLeaf(lib, "SaySomething", {text("message", "Hello, I am here!"), num("speak_duration", "2.0")},
          [](auto& n, TickContext& c) {
            c.memory.social.speaking_until = now(c) + std::max<std::int64_t>(usOf(n.value(1, c)), usOf(c.dt));
            c.memory.social.message = n.portValue(0).text;
            return true;
          });
  addLeaf(lib, "SetGroupId", {req("group_id")}, [](auto& n, TickContext& c) {
    c.memory.group_override = std::max(-1, static_cast<int>(n.value(0, c)));
    c.out.group_id = c.memory.group_override;
    return true;
  });

  lib.addNode<SetGoalNode>("SetGoal", Kind::Leaf, {num("goal_id", "-1"), num("x", "0.0"), num("y", "0.0")});
  setPointCheck(lib, "SetGoal", "goal_id", "x", "y");

  // --- stateful actions
  addStateful<StopAndWait>(lib, "StopAndWaitTimerAction", {num("wait_duration", "3.0")});
  addStateful<Approach>(lib, "ApproachRobot",
                        {num("closest_dist", "1.5"), num("max_vel", "1.8"), num("duration", "5.0")}, TargetPort::None);
  addStateful<Approach>(
      lib, "ApproachAgent",
      {req("target_agent_id"), num("closest_dist", "0.5"), num("max_vel", "1.0"), num("duration", "5.0")},
      TargetPort::First);
  addStateful<Block>(lib, "BlockRobot", {num("front_dist", "1.0"), num("duration", "5.0")}, TargetPort::None);
  addStateful<Block>(lib, "BlockAgent", {req("target_agent_id"), num("front_dist", "1.0"), num("duration", "5.0")},
                     TargetPort::First);
  addStateful<AvoidRobot>(lib, "AvoidRobot",
                          {num("safe_distance", "5.0"), num("runaway_vel", "1.0"), num("duration", "0.0")});
  addStateful<FollowAgent>(
      lib, "FollowAgent",
      {req("target_agent_id"), num("closest_dist", "1.5"), num("max_vel", "1.5"), num("duration", "0.0")});
  addStateful<GroupWalk>(lib, "SetGroupWalk",
                         {req("main_agent_id"), ids("non_main_agent_ids"), num("duration", "5.0")});
  addStateful<ConversationFormation>(
      lib, "ConversationFormation",
      {req("main_agent_id"), ids("non_main_agent_ids"), num("conversation_duration", "10.0"), num("goal_id", "-1"),
       num("center_x", "0.0"), num("center_y", "0.0"), num("radius", "0.0"), num("start_angle", "0.0")});
  lib.findMutable("ConversationFormation")->check = [](const std::vector<PortSpec>& s,
                                                       const std::vector<PortValue>& v) {
    return pointCheck(s, v, "goal_id", "center_x", "center_y");
  };
  lib.addNode<GoTo>("GoTo", Kind::Leaf,
                    {num("goal_id", "-1"), num("x", "0.0"), num("y", "0.0"), num("tolerance", "0.1")});
  setPointCheck(lib, "GoTo", "goal_id", "x", "y");
  lib.addNode<LookAt>("LookAtAgent", Kind::Leaf, {num("observer_id", "{id}"), req("target_id")}, LookTarget::Agent);
  lib.findMutable("LookAtAgent")->check = observerIsSelf;
  lib.addNode<LookAt>("LookAtRobot", Kind::Leaf, {}, LookTarget::Robot);
  lib.addNode<LookAt>("LookAtPoint", Kind::Leaf, {num("goal_id", "-1"), num("x", "0.0"), num("y", "0.0")},
                      LookTarget::Point);
  setPointCheck(lib, "LookAtPoint", "goal_id", "x", "y");

  // --- decorator
  lib.addNode<TimeDelay>("TimeDelay", Kind::Decorator, {num("delay", "1.0")});

  for (const char* name : {"IsAnyoneSpeaking", "IsSpeaking", "SaySomething", "ConversationFormation", "LookAtAgent",
                           "LookAtRobot", "LookAtPoint"})
    markSocial(lib, name);
}

bool usesSocialNodes(const BtSpec& root, const NodeLibrary& lib) {
  const NodeLibrary::Entry* e = lib.find(root.name);
  if (e != nullptr && e->social) return true;
  for (const BtSpec& c : root.children)
    if (usesSocialNodes(c, lib)) return true;
  return false;
}

namespace {
void checkGoalIdsIn(const BtSpec& s, const NodeLibrary& lib, const std::map<int, Vec2>& goals,
                    const std::string& file) {
  if (const NodeLibrary::Entry* e = lib.find(s.name)) {
    for (std::size_t i = 0; i < e->ports.size() && i < s.ports.size(); ++i) {
      const PortValue& v = s.ports[i];
      if (e->ports[i].name != "goal_id" || !v.given || v.from_blackboard) continue;
      const double id = v.number;
      if (id != std::floor(id) || goals.count(static_cast<int>(id)) == 0) {
        std::string known;
        for (const auto& [k, p] : goals) known += (known.empty() ? "" : ", ") + std::to_string(k);
        throw ConfigError(file, s.line, "",
                          s.name + ": port goal_id: '" + v.text + "' is not an id of the scenario's global_goals (" +
                              (known.empty() ? std::string("it has none") : "ids " + known) +
                              "); add it there, or give the point as x and y");
      }
    }
  }
  for (const BtSpec& c : s.children) checkGoalIdsIn(c, lib, goals, file);
}
}  // namespace

void checkGoalIds(const TreeDefinition& tree, const NodeLibrary& lib, const std::map<int, Vec2>& goals) {
  checkGoalIdsIn(tree.root(), lib, goals, tree.file());
}

}  // namespace hunav::manager
