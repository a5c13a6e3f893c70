// The HuNavSim node library: conditions and actions (manager/README.md, "Behavior trees").
#include <algorithm>
#include <cmath>

#include "bt_social.hpp"
#include "hunav/manager/agent_manager.hpp"
#include "hunav/manager/behavior_tree.hpp"
#include "hunav/manager/hunav_nodes.hpp"

namespace hunav::manager {

void standStill(TickContext& c) {
  c.out.x = c.in.x;
  c.out.y = c.in.y;
  c.out.vx = c.out.vy = 0.0;
  c.out.linear_vel = 0.0;
  c.out.angular_vel = c.out.vyaw = 0.0;
  c.out.yaw = c.in.yaw;
  c.memory.moved = true;
}

namespace {

using Kind = NodeLibrary::Kind;

Vec2 agentPos(const TickContext& c) { return Vec2(c.in.x, c.in.y); }
Vec2 robotPos(const TickContext& c) { return Vec2(c.snap.request->robot.x, c.snap.request->robot.y); }
// Without the robot (AgentManager::setRobotAbsent) no condition on it holds and no reaction to it runs.
bool noRobot(const TickContext& c) { return c.snap.robot_absent; }
void setActive(TickContext& c) { c.out.behavior_state = agent_state_t::STATE_ACTIVE_1; }

// A node defined by a lambda over the context and its own port reader.
template <class F>
class LambdaNode : public BtNode {
 public:
  explicit LambdaNode(F f) : f_(std::move(f)) {}

 protected:
  Status onTick(TickContext& c) override { return f_(*this, c) ? Status::Success : Status::Failure; }

 public:
  double value(std::size_t i, const TickContext& c) const { return number(i, c); }
  // A port with choices: the position of its value in the list.
  int choice(std::size_t i) const { return static_cast<int>(port(i).number); }

 private:
  F f_;
};

template <class F>
void addLeaf(NodeLibrary& lib, const std::string& name, std::vector<PortSpec> ports, F f) {
  lib.addNode<LambdaNode<F>>(name, Kind::Leaf, std::move(ports), f);
}

PortSpec num(const std::string& name, const std::string& def) {
  return PortSpec{name, PortType::Number, false, def, {}};
}
PortSpec flag(const std::string& name, const std::string& def) {
  return PortSpec{name, PortType::Bool, false, def, {}};
}

// TimeExpiredCondition(seconds, only_once, ts): adds ts (default {dt}, simulation time) on every tick;
// FAILURE until `seconds` have accumulated, then SUCCESS (and restarts unless only_once).
class TimeExpired : public BtNode {
 protected:
  Status onTick(TickContext& c) override {
    acc_ += number(2, c);
    if (acc_ + 1e-9 < number(0, c)) return Status::Failure;
    if (!flag(1, c)) acc_ = 0.0;
    return Status::Success;
  }

 private:
  double acc_ = 0.0;
};

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// RandomChance(probability): SUCCESS with that probability. The draw depends only on the episode,
// the agent id, the node's position in the tree and how often it was ticked: reproducible.
class RandomChance : public BtNode {
 protected:
  Status onTick(TickContext& c) override {
    std::uint64_t h = splitmix(static_cast<std::uint64_t>(c.episode));
    h = splitmix(h ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.in.id)));
    h = splitmix(h ^ static_cast<std::uint64_t>(nodeIndex()));
    h = splitmix(h ^ counter_++);
    const double u = static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
    return u < number(0, c) ? Status::Success : Status::Failure;
  }

 private:
  std::uint64_t counter_ = 0;
};

void registerHunavNodes(NodeLibrary& lib) {
  // --- conditions
  addLeaf(lib, "IsRobotVisible", {num("distance", "5.0")}, [](auto& n, TickContext& c) {
    if (!c.in.robot_in_sight || noRobot(c)) return false;
    const Vec2 d = robotPos(c) - agentPos(c);
    const double range = n.value(0, c);
    if (d.squaredNorm() > range * range) return false;
    return std::abs(normalizeAngle(angleOf(d) - c.in.yaw)) <= kHalfFieldOfView;
  });
  addLeaf(lib, "IsGoalReached", {}, [](auto&, TickContext& c) {
    if (c.out.goals.empty()) return false;
    const point2d_t& g = c.out.goals.front();
    return std::hypot(g.x - c.out.x, g.y - c.out.y) <= c.out.goal_radius + kGoalSwitchMargin;
  });
  addLeaf(lib, "IsRobotClose", {num("threshold", "1.0")},
          [](auto& n, TickContext& c) { return !noRobot(c) && (robotPos(c) - agentPos(c)).norm() < n.value(0, c); });
  addLeaf(lib, "IsRobotFacingAgent", {num("angle", "0.3")}, [](auto& n, TickContext& c) {
    if (noRobot(c)) return false;
    const double b = normalizeAngle(angleOf(agentPos(c) - robotPos(c)) - c.snap.request->robot.yaw);
    return std::abs(b) < n.value(0, c);
  });
  lib.addNode<TimeExpired>("TimeExpiredCondition", Kind::Leaf,
                           {num("seconds", "1.0"), flag("only_once", "false"), num("ts", "{dt}")});
  lib.addNode<RandomChance>("RandomChance", Kind::Leaf, {num("probability", "0.3")});
  // HuNavSim 2.0's name of the same node.
  lib.addNode<RandomChance>("RandomChanceCondition", Kind::Leaf, {num("probability", "0.3")});

  // --- goal queue
  addLeaf(lib, "UpdateGoal", {}, [](auto&, TickContext& c) {
    if (c.out.goals.empty()) return true;
    const point2d_t g = c.out.goals.front();
    c.out.goals.erase(c.out.goals.begin());
    if (c.out.cyclic_goals) c.out.goals.push_back(g);
    c.out.num_goals = static_cast<int32_t>(c.out.goals.size());
    return true;
  });

  // --- motion
  // RegularNav(robot = auto | person | obstacle): social force navigation; auto = obstacle for
  // impassive agents, a person for everybody else.
  enum RobotMode { kAuto, kPerson, kObstacle };
  addLeaf(lib, "RegularNav", {PortSpec{"robot", PortType::String, false, "auto", {"auto", "person", "obstacle"}}},
          [](auto& n, TickContext& c) {
            const int mode = n.choice(0);
            RobotAs as = RobotAs::Person;
            if (mode == kObstacle || (mode == kAuto && c.in.behavior == agent_state_t::BEH_IMPASSIVE))
              as = RobotAs::Obstacle;
            regularMove(c, as);
            c.out.behavior_state = agent_state_t::STATE_INACTIVE;
            return true;
          });
  // SurprisedNav: stop and turn toward the robot at kTurnRate (stops turning once facing it).
  addLeaf(lib, "SurprisedNav", {}, [](auto&, TickContext& c) {
    if (noRobot(c)) return false;
    standStill(c);
    turnToward(c, robotPos(c), kTurnRate * c.dt);
    setActive(c);
    return true;
  });
  // CuriousNav(stop_distance, agent_vel): approach the robot at vel*d/(d+stop) (robot excluded from
  // the social force); within stop_distance stand and face it.
  addLeaf(lib, "CuriousNav", {num("stop_distance", "1.5"), num("agent_vel", "1.0")}, [](auto& n, TickContext& c) {
    if (noRobot(c)) return false;
    const Vec2 r = robotPos(c);
    const double d = (r - agentPos(c)).norm();
    const double stop = n.value(0, c);
    if (d <= stop) {
      standStill(c);
      turnToward(c, r, kTurnRate * c.dt);
    } else {
      sfmMove(c, RobotAs::Ignored, n.value(1, c) * d / (d + stop), &r, Vec2::Zero(), c.snap.request->robot.radius);
    }
    setActive(c);
    return true;
  });
  // ScaredNav(runaway_vel, scary_force_factor): regular navigation at runaway_vel (robot excluded)
  // plus K * sigma_o / d_eff away from the robot (HuNavSim 1's scared reaction; manager/README.md).
  addLeaf(lib, "ScaredNav", {num("runaway_vel", "0.6"), num("scary_force_factor", "20.0")},
          [](auto& n, TickContext& c) {
            if (noRobot(c)) return false;
            const Vec2 away = agentPos(c) - robotPos(c);
            const double len = away.norm();
            Vec2 extra = Vec2::Zero();
            if (len > 0.0) {
              const double d_eff = std::max(len - c.in.radius, 0.01);
              extra = n.value(1, c) * (SfmParams{}.obstacle_sigma / d_eff) * (away / len);
            }
            sfmMove(c, RobotAs::Ignored, n.value(0, c), nullptr, extra);
            setActive(c);
            return true;
          });
  // ThreateningNav(goal_dist, speed): run to the point goal_dist in front of the robot, along its
  // heading (cos h, sin h); once there, face the robot.
  addLeaf(lib, "ThreateningNav", {num("goal_dist", "1.4"), num("speed", "2.0")}, [](auto& n, TickContext& c) {
    if (noRobot(c)) return false;
    const agent_state_t& robot = c.snap.request->robot;
    const Vec2 r = robotPos(c);
    const Vec2 front = r + n.value(0, c) * Vec2(std::cos(robot.yaw), std::sin(robot.yaw));
    sfmMove(c, RobotAs::Ignored, n.value(1, c), &front, Vec2::Zero(), 0.05);
    if ((Vec2(c.out.x, c.out.y) - front).norm() <= 0.3) turnToward(c, r, kPi);
    setActive(c);
    return true;
  });
  addLeaf(lib, "StopMovement", {}, [](auto&, TickContext& c) {
    c.memory.stopped = true;
    standStill(c);
    return true;
  });
  addLeaf(lib, "ResumeMovement", {}, [](auto&, TickContext& c) {
    c.memory.stopped = false;
    return true;
  });
  registerSocialNodes(lib);  // HuNavSim 2.0's library (bt_social.cpp)
}

}  // namespace

NodeLibrary hunavNodeLibrary() {
  NodeLibrary lib = NodeLibrary::withBuiltins();
  const std::vector<std::string> engine_nodes = lib.names();
  registerHunavNodes(lib);
  // Every leaf of the HuNavSim library takes HuNavSim's agent_id / time_step ports (bt_xml.cpp).
  for (const std::string& name : lib.names()) {
    NodeLibrary::Entry* entry = lib.findMutable(name);
    const bool engine = std::find(engine_nodes.begin(), engine_nodes.end(), name) != engine_nodes.end();
    if (!engine && entry->kind == Kind::Leaf) entry->agent_ports = true;
  }
  return lib;
}

}  // namespace hunav::manager
