#include "hunav/manager/agent_manager.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hunav::manager {

namespace {

SfmBody bodyOf(const agent_state_t& a) {
  SfmBody b;
  b.id = a.id;
  b.group_id = a.group_id;
  b.position = Vec2(a.x, a.y);
  b.velocity = Vec2(a.vx, a.vy);
  b.radius = a.radius;
  return b;
}

// atan2 without libm: octant reduction, then |a| <= tan(pi/8) and the odd Taylor series of atan to
// degree 21 (truncation error < 1e-10 rad).
inline double fastAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (mx == 0.0) return 0.0;
  double a = mn / mx, base = 0.0;
  if (a > 0.41421356237309503) {
    a = (a - 1.0) / (a + 1.0);
    base = kPi / 4.0;
  }
  const double s = a * a;
  // atan(a) = a * sum_k (-1)^k s^k / (2k + 1), k = 0..10, Horner from k = 10.
  double poly = 1.0 / 21;
  for (int k = 9; k >= 0; --k) poly = poly * s + ((k % 2 == 0) ? 1.0 : -1.0) / (2 * k + 1);
  double r = base + a * poly;
  if (ay > ax) r = kPi / 2.0 - r;
  if (x < 0.0) r = kPi - r;
  return y < 0.0 ? -r : r;
}

// The social force of section 1.5 of body j on body i, without the weight omega_s (same formula as
// hunav::socialForceFrom, atan2 replaced by fastAtan2). The force of i on j is exactly the opposite
// (D_ji = -D_ij, so t flips and theta is unchanged), so each pair is evaluated once.
inline Vec2 unitSocial(const SfmBody& me, const SfmBody& o, const SfmParams& p) {
  const double dx = o.position.x() - me.position.x(), dy = o.position.y() - me.position.y();
  const double d2 = dx * dx + dy * dy;
  if (d2 <= 0.0) return Vec2::Zero();
  const double d = std::sqrt(d2), inv_d = 1.0 / d;
  const double ex = dx * inv_d, ey = dy * inv_d;
  const double Dx = p.lambda * (me.velocity.x() - o.velocity.x()) + ex;
  const double Dy = p.lambda * (me.velocity.y() - o.velocity.y()) + ey;
  const double len2 = Dx * Dx + Dy * Dy;
  if (len2 <= 0.0) return Vec2::Zero();
  const double len = std::sqrt(len2), inv_len = 1.0 / len;
  const double B = p.gamma * len;
  const double a = d * inv_len / p.gamma;
  const double tx = Dx * inv_len, ty = Dy * inv_len;
  const double theta = fastAtan2(tx * ey - ty * ex, tx * ex + ty * ey);
  const double q = p.n * B * theta, qp = p.n_prime * B * theta;
  const double fv = -std::exp(-a - qp * qp);
  const double sign = theta > 0.0 ? 1.0 : (theta < 0.0 ? -1.0 : 0.0);
  const double ft = -sign * std::exp(-a - q * q);
  return Vec2(fv * tx - ft * ty, fv * ty + ft * tx);
}

ForceSet forcesImpl(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                    double goal_radius, RobotAs robot, double desired_speed) {
  const SfmParams p = paramsOf(a);
  const SfmBody& me = snap.agents[index];
  ForceSet f;
  Vec2 direction = Vec2::Zero();
  f.desired = desiredForce(me, goal, goal_radius, desired_speed, p, &direction);

  for (const point2d_t& o : a.obstacles) f.obstacle += obstacleForceFrom(me, Vec2(o.x, o.y), p);
  if (robot == RobotAs::Obstacle) f.obstacle += obstacleForceFrom(me, snap.robot.position, p);

  if (snap.people_social.size() == snap.agents.size()) {
    f.social = p.social_weight * snap.people_social[index];
  } else if (snap.by_id.size() == snap.agents.size()) {
    for (int j : snap.by_id)
      if (static_cast<std::size_t>(j) != index) f.social += socialForceFrom(me, snap.agents[j], p);
  } else {
    for (std::size_t j = 0; j < snap.agents.size(); ++j)
      if (j != index) f.social += socialForceFrom(me, snap.agents[j], p);
  }
  if (robot == RobotAs::Person) f.social += socialForceFrom(me, snap.robot, p);

  if (me.group_id >= 0) {
    std::vector<const SfmBody*> mates;
    auto it = snap.groups.find(me.group_id);
    if (it != snap.groups.end()) {
      for (int j : it->second)
        if (static_cast<std::size_t>(j) != index) mates.push_back(&snap.agents[j]);
    } else {
      for (std::size_t j = 0; j < snap.agents.size(); ++j)
        if (j != index && snap.agents[j].group_id == me.group_id) mates.push_back(&snap.agents[j]);
    }
    f.group = groupForces(me, mates, direction, p).total();
  }
  f.finish();
  return f;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------

void NeighborGrid::build(const std::vector<SfmBody>& bodies, const std::vector<int>& order, double cell) {
  bodies_ = &bodies;
  items_.clear();
  start_.clear();
  nx_ = ny_ = 0;
  if (bodies.empty()) return;
  Vec2 lo = bodies[0].position, hi = lo;
  for (const SfmBody& b : bodies) {
    lo = lo.cwiseMin(b.position);
    hi = hi.cwiseMax(b.position);
  }
  cell_ = cell;
  // Keep the grid at most ~4 cells per body (people spread far apart: bigger cells, same result).
  const double max_cells = 4.0 * static_cast<double>(bodies.size()) + 16.0;
  while (((hi.x() - lo.x()) / cell_ + 1.0) * ((hi.y() - lo.y()) / cell_ + 1.0) > max_cells) cell_ *= 2.0;
  origin_ = lo;
  nx_ = static_cast<int>(std::floor((hi.x() - lo.x()) / cell_)) + 1;
  ny_ = static_cast<int>(std::floor((hi.y() - lo.y()) / cell_)) + 1;
  start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  auto cellOf = [&](const Vec2& p) {
    const int x = std::min(static_cast<int>(std::floor((p.x() - lo.x()) / cell_)), nx_ - 1);
    const int y = std::min(static_cast<int>(std::floor((p.y() - lo.y()) / cell_)), ny_ - 1);
    return y * nx_ + x;
  };
  for (const SfmBody& b : bodies) ++start_[cellOf(b.position) + 1];
  for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
  items_.resize(bodies.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (int j : order) items_[fill[cellOf(bodies[j].position)]++] = j;  // id order within a cell
}

void computePeopleSocial(StepSnapshot& snap, const NeighborGrid& grid, double cutoff) {
  snap.people_social.assign(snap.agents.size(), Vec2::Zero());
  const SfmParams p;  // lambda, gamma, n, n' are the same for everybody; omega_s is applied per agent
  grid.forEachPair(cutoff, [&](int i, int j) {
    const Vec2 u = unitSocial(snap.agents[i], snap.agents[j], p);
    snap.people_social[i] += u;
    snap.people_social[j] -= u;
  });
}

void StepSnapshot::index() {
  by_id.resize(agents.size());
  std::iota(by_id.begin(), by_id.end(), 0);
  std::sort(by_id.begin(), by_id.end(), [&](int a, int b) { return agents[a].id < agents[b].id; });
  groups.clear();
  for (int j : by_id)
    if (agents[j].group_id >= 0) groups[agents[j].group_id].push_back(j);
}

SfmParams paramsOf(const agent_state_t& a) {
  SfmParams p;
  p.goal_weight = a.behavior_params.goal_force_factor;
  p.obstacle_weight = a.behavior_params.obstacle_force_factor;
  p.social_weight = a.behavior_params.social_force_factor;
  return p;
}

ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       RobotAs robot, double desired_speed) {
  return forcesImpl(snap, index, a, goal, a.goal_radius, robot, desired_speed);
}

ForceSet computeForces(const StepSnapshot& snap, std::size_t index, const agent_state_t& a, const Vec2* goal,
                       bool robot_as_obstacle) {
  return forcesImpl(snap, index, a, goal, a.goal_radius, robot_as_obstacle ? RobotAs::Obstacle : RobotAs::Person,
                    a.desired_speed);
}

void sfmMove(TickContext& c, RobotAs robot, double speed, const Vec2* goal, const Vec2& extra, double goal_radius) {
  if (c.memory.stopped) speed = 0.0;
  Vec2 g;
  if (goal == nullptr && !c.out.goals.empty()) {
    g = Vec2(c.out.goals.front().x, c.out.goals.front().y);
    goal = &g;
  }
  ForceSet f = forcesImpl(c.snap, c.index, c.in, goal, goal_radius >= 0.0 ? goal_radius : c.in.goal_radius, robot,
                          speed);
  if (std::isfinite(extra.x()) && std::isfinite(extra.y())) f.total += extra;
  const SfmMotion m = integrate(Vec2(c.in.x, c.in.y), Vec2(c.in.vx, c.in.vy), c.in.yaw, f.total, speed, c.dt);
  c.out.x = m.position.x();
  c.out.y = m.position.y();
  c.out.vx = m.velocity.x();
  c.out.vy = m.velocity.y();
  c.out.yaw = m.yaw;
  c.out.linear_vel = m.linear_vel;
  c.out.angular_vel = m.angular_vel;
  c.out.vyaw = m.angular_vel;
  c.memory.moved = true;
}

void turnToward(TickContext& c, const Vec2& target, double max_step) {
  const Vec2 d = target - Vec2(c.out.x, c.out.y);
  if (d.squaredNorm() == 0.0) return;
  const double err = normalizeAngle(angleOf(d) - c.out.yaw);
  const double step = std::clamp(err, -max_step, max_step);
  c.out.yaw = normalizeAngle(c.out.yaw + step);
  c.out.angular_vel = c.dt > 0.0 ? normalizeAngle(c.out.yaw - c.in.yaw) / c.dt : 0.0;
  c.out.vyaw = c.out.angular_vel;
}

// ---------------------------------------------------------------------------------------------------

AgentManager::AgentManager() : lib_(NodeLibrary::withBuiltins()) {}

void AgentManager::setBuiltinTree(int behavior, const std::string& xml) {
  builtin_override_[behavior] = xml;
  definitions_.erase("builtin:" + std::to_string(behavior));
  memory_.clear();
}

void AgentManager::loadTreeFile(const std::string& path) {
  if (definitions_.count(path) == 0) definitions_[path] = TreeDefinition::load(path, lib_);
}

std::shared_ptr<const TreeDefinition> AgentManager::definitionFor(const agent_state_t& a, std::string& source) {
  if (!a.behavior_tree.empty()) {
    source = a.behavior_tree;
    loadTreeFile(source);
    return definitions_[source];
  }
  int code = a.behavior;
  if (code < agent_state_t::BEH_REGULAR || code > agent_state_t::BEH_THREATENING) code = agent_state_t::BEH_REGULAR;
  source = "builtin:" + std::to_string(code);
  auto it = definitions_.find(source);
  if (it != definitions_.end()) return it->second;
  auto o = builtin_override_.find(code);
  const std::string& xml = o != builtin_override_.end() ? o->second : builtinTreeXml(code);
  return definitions_[source] = TreeDefinition::parse(xml, std::string("behavior_trees/") + builtinTreeName(code), lib_);
}

AgentMemory& AgentManager::memoryFor(const agent_state_t& a) {
  AgentMemory& m = memory_[a.id];
  if (m.tree && m.behavior == a.behavior && m.tree_file == a.behavior_tree) return m;  // unchanged
  m.behavior = a.behavior;
  m.tree_file = a.behavior_tree;
  std::string source;
  auto def = definitionFor(a, source);
  if (!m.tree || m.tree_source != source) {
    m.tree = def->instantiate(lib_);
    m.tree_source = source;
    m.stopped = false;
  }
  return m;
}

step_reply_t AgentManager::step(const step_request_t& request) {
  if (!have_episode_ || request.episode != episode_) {
    memory_.clear();
    episode_ = request.episode;
    have_episode_ = true;
  }
  StepSnapshot snap;
  snap.request = &request;
  snap.agents.reserve(request.agents.size());
  for (const agent_state_t& a : request.agents) snap.agents.push_back(bodyOf(a));
  snap.robot = bodyOf(request.robot);
  snap.index();
  if (cutoff_ > 0.0) {
    grid_.build(snap.agents, snap.by_id, cutoff_);
    computePeopleSocial(snap, grid_, cutoff_);
  }

  step_reply_t reply;
  reply.utime = request.utime + static_cast<int64_t>(std::llround(request.dt * 1e6));
  reply.seq = request.seq;
  reply.episode = request.episode;
  reply.num_agents = request.num_agents;
  reply.agents = request.agents;
  for (std::size_t i = 0; i < request.agents.size(); ++i) {
    const agent_state_t& in = request.agents[i];
    agent_state_t& out = reply.agents[i];
    out.utime = reply.utime;
    out.behavior_state = agent_state_t::STATE_INACTIVE;
    AgentMemory& mem = memoryFor(in);
    mem.moved = false;
    TickContext ctx{snap, i, in, out, request.dt, request.episode, request.seq, mem, {}};
    auto set = [&](BbKey k, double v) { ctx.bb[static_cast<std::size_t>(k)] = v; };
    const behavior_params_t& bp = in.behavior_params;
    set(BbKey::Id, in.id);
    set(BbKey::Dt, request.dt);
    set(BbKey::Time, static_cast<double>(request.utime) * 1e-6);
    set(BbKey::Dist, bp.dist);
    set(BbKey::Duration, bp.duration);
    set(BbKey::Once, bp.once ? 1.0 : 0.0);
    set(BbKey::Vel, bp.vel);
    set(BbKey::GoalForceFactor, bp.goal_force_factor);
    set(BbKey::ObstacleForceFactor, bp.obstacle_force_factor);
    set(BbKey::SocialForceFactor, bp.social_force_factor);
    set(BbKey::OtherForceFactor, bp.other_force_factor);
    set(BbKey::MaxVel, in.desired_speed);
    mem.tree->tick(ctx);
  }
  return reply;
}

}  // namespace hunav::manager
