#include "hunav/fingerprint.hpp"

#include <xxhash.h>

#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace hunav {

void Fingerprint::add(const void* data, std::size_t size) { hash_ = XXH3_64bits_withSeed(data, size, hash_); }

namespace {

// LCM's wire format: integers and the bits of doubles big-endian, booleans one byte, strings as an
// int32 length (with the NUL) then the bytes and the NUL.
class Writer {
 public:
  explicit Writer(std::uint8_t* p) : p_(p) {}
  std::uint8_t* position() const { return p_; }
  void i8(std::int8_t v) { *p_++ = static_cast<std::uint8_t>(v); }
  void i32(std::int32_t v) {
    const std::uint32_t be = __builtin_bswap32(static_cast<std::uint32_t>(v));
    std::memcpy(p_, &be, 4);
    p_ += 4;
  }
  void i64(std::int64_t v) {
    const std::uint64_t be = __builtin_bswap64(static_cast<std::uint64_t>(v));
    std::memcpy(p_, &be, 8);
    p_ += 8;
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    i64(static_cast<std::int64_t>(bits));
  }
  void str(const std::string& s) {  // after stringSize(s): no NUL inside
    const std::size_t n = s.size() + 1;
    i32(static_cast<std::int32_t>(n));
    std::memcpy(p_, s.c_str(), n);
    p_ += n;
  }

 private:
  std::uint8_t* p_;
};

std::size_t stringSize(const std::string& s) {
  // The generated code sizes a string by size() but writes it up to its first NUL, and Bus::encode
  // refuses such a message: the same here.
  if (std::strlen(s.c_str()) != s.size()) throw std::runtime_error("cannot encode a message (a string holds a NUL)");
  return 4 + s.size() + 1;
}

// Bytes of an agent_state_t: the fixed fields (8 + 4 + 1 + 1 + 1 + behavior_params 58 + 4 + 10 * 8 +
// 4 + 8 + 1 + 4 + 1 = 175), the two strings and 16 per point.
std::size_t agentSize(const agent_state_t& a) {
  constexpr std::size_t kFixed = 175;
  return kFixed + stringSize(a.name) + stringSize(a.behavior_tree) +
         16 * static_cast<std::size_t>(a.num_goals + a.num_obstacles);
}

void writeAgent(Writer& w, const agent_state_t& a) {
  w.i64(a.utime);
  w.i32(a.id);
  w.i8(a.type);
  w.str(a.name);
  w.i8(a.behavior);
  w.i8(a.behavior_state);
  const behavior_params_t& bp = a.behavior_params;
  w.i8(bp.configuration);
  w.f64(bp.duration);
  w.i8(bp.once);
  w.f64(bp.vel);
  w.f64(bp.dist);
  w.f64(bp.goal_force_factor);
  w.f64(bp.obstacle_force_factor);
  w.f64(bp.social_force_factor);
  w.f64(bp.other_force_factor);
  w.str(a.behavior_tree);
  w.i32(a.group_id);
  for (const double v : {a.x, a.y, a.yaw, a.vx, a.vy, a.vyaw, a.linear_vel, a.angular_vel, a.radius, a.desired_speed})
    w.f64(v);
  w.i32(a.num_goals);
  for (int k = 0; k < a.num_goals; ++k) {
    w.f64(a.goals[static_cast<std::size_t>(k)].x);
    w.f64(a.goals[static_cast<std::size_t>(k)].y);
  }
  w.f64(a.goal_radius);
  w.i8(a.cyclic_goals);
  w.i32(a.num_obstacles);
  for (int k = 0; k < a.num_obstacles; ++k) {
    w.f64(a.obstacles[static_cast<std::size_t>(k)].x);
    w.f64(a.obstacles[static_cast<std::size_t>(k)].y);
  }
  w.i8(a.robot_in_sight);
}

}  // namespace

void encodeWorldState(const world_state_t& ws, std::vector<std::uint8_t>& out) {
  // hash, utime, tick, episode, the robot, num_agents, the agents, num_collisions, 43 per collision
  // (1 + 4 + 1 + 4 + 4 * 8 + 1).
  constexpr std::size_t kCollision = 43;
  std::size_t size = 8 + 3 * 8 + agentSize(ws.robot) + 4 + 4 + kCollision * static_cast<std::size_t>(ws.num_collisions);
  for (int i = 0; i < ws.num_agents; ++i) size += agentSize(ws.agents[static_cast<std::size_t>(i)]);
  out.resize(size);
  Writer w(out.data());
  w.i64(world_state_t::getHash());
  w.i64(ws.utime);
  w.i64(ws.tick);
  w.i64(ws.episode);
  writeAgent(w, ws.robot);
  w.i32(ws.num_agents);
  for (int i = 0; i < ws.num_agents; ++i) writeAgent(w, ws.agents[static_cast<std::size_t>(i)]);
  w.i32(ws.num_collisions);
  for (int i = 0; i < ws.num_collisions; ++i) {
    const collision_t& c = ws.collisions[static_cast<std::size_t>(i)];
    w.i8(c.kind_a);
    w.i32(c.id_a);
    w.i8(c.kind_b);
    w.i32(c.id_b);
    w.f64(c.x);
    w.f64(c.y);
    w.f64(c.normal_speed);
    w.f64(c.impulse);
    w.i8(c.caused_by);
  }
  if (w.position() != out.data() + out.size()) throw std::logic_error("encodeWorldState: size mismatch");
}

std::string Fingerprint::hex() const {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash_));
  return buf;
}

}  // namespace hunav
