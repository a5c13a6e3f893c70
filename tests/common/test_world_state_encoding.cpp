#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <hunav/laser_scan_t.hpp>
#include <hunav/live_metrics_t.hpp>
#include <hunav/map_t.hpp>
#include <hunav/wire_codec.hpp>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "hunav/fingerprint.hpp"

using namespace hunav;

namespace {

template <class Msg>
std::vector<std::uint8_t> lcmEncoding(const Msg& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return bytes;
}

// The generated codec's encoding of `m` (wire_codec.hpp): the hash, then writeBody.
template <class Msg>
std::vector<std::uint8_t> codecEncoding(const Msg& m) {
  std::vector<std::uint8_t> bytes(8 + wire::bodySize(m));
  wire::Writer w(bytes.data());
  w.i64(Msg::getHash());
  wire::writeBody(w, m);
  EXPECT_EQ(w.position(), bytes.data() + bytes.size());
  return bytes;
}

// Every field random (doubles from raw bits too: NaN, infinities, subnormals, -0), strings of any
// length, 0 to 4 goals and obstacles.
agent_state_t randomAgent(std::mt19937_64& rng) {
  auto anyDouble = [&] {
    if (rng() % 4 == 0) {
      const std::uint64_t bits = rng();
      double v;
      std::memcpy(&v, &bits, sizeof v);
      return v;
    }
    return std::uniform_real_distribution<double>(-100.0, 100.0)(rng);
  };
  auto anyString = [&] {
    std::string s(rng() % 20, 'a');
    for (char& c : s) c = static_cast<char>('a' + rng() % 26);
    return s;
  };
  auto points = [&] {
    std::vector<point2d_t> p(rng() % 5);
    for (auto& q : p) q = point2d_t{anyDouble(), anyDouble()};
    return p;
  };
  agent_state_t a{};
  a.utime = static_cast<std::int64_t>(rng());
  a.id = static_cast<std::int32_t>(rng());
  a.type = static_cast<std::int8_t>(rng());
  a.name = anyString();
  a.behavior = static_cast<std::int8_t>(rng());
  a.behavior_state = static_cast<std::int8_t>(rng());
  behavior_params_t& bp = a.behavior_params;
  bp.configuration = static_cast<std::int8_t>(rng());
  bp.duration = anyDouble();
  bp.once = static_cast<std::int8_t>(rng() % 2);
  bp.vel = anyDouble();
  bp.dist = anyDouble();
  bp.goal_force_factor = anyDouble();
  bp.obstacle_force_factor = anyDouble();
  bp.social_force_factor = anyDouble();
  bp.other_force_factor = anyDouble();
  a.behavior_tree = rng() % 2 ? anyString() : "";
  a.group_id = static_cast<std::int32_t>(rng());
  for (double* v : {&a.x, &a.y, &a.yaw, &a.vx, &a.vy, &a.vyaw, &a.linear_vel, &a.angular_vel, &a.radius,
                    &a.desired_speed, &a.goal_radius})
    *v = anyDouble();
  a.goals = points();
  a.num_goals = static_cast<std::int32_t>(a.goals.size());
  a.cyclic_goals = static_cast<std::int8_t>(rng() % 2);
  a.obstacles = points();
  a.num_obstacles = static_cast<std::int32_t>(a.obstacles.size());
  a.robot_in_sight = static_cast<std::int8_t>(rng() % 2);
  return a;
}

}  // namespace

TEST(WorldStateEncoding, IsLcmsEncodingByteForByte) {
  std::mt19937_64 rng(11);
  std::vector<std::uint8_t> ours;
  for (int round = 0; round < 200; ++round) {
    world_state_t ws{};
    ws.utime = static_cast<std::int64_t>(rng());
    ws.tick = static_cast<std::int64_t>(rng());
    ws.episode = -static_cast<std::int64_t>(rng() % 1000);
    ws.robot = randomAgent(rng);
    ws.agents.resize(rng() % 30);
    for (auto& a : ws.agents) a = randomAgent(rng);
    ws.num_agents = static_cast<std::int32_t>(ws.agents.size());
    ws.collisions.resize(rng() % 4);
    for (auto& c : ws.collisions) {
      c.kind_a = static_cast<std::int8_t>(rng());
      c.id_a = static_cast<std::int32_t>(rng());
      c.kind_b = static_cast<std::int8_t>(rng());
      c.id_b = static_cast<std::int32_t>(rng());
      c.x = static_cast<double>(rng() % 1000) / 7.0;
      c.y = -c.x;
      c.normal_speed = std::numeric_limits<double>::infinity();
      c.impulse = std::nan("");
      c.caused_by = static_cast<std::int8_t>(rng() % 3);
    }
    ws.num_collisions = static_cast<std::int32_t>(ws.collisions.size());
    encodeWorldState(ws, ours);  // reusing the buffer of the previous round, larger or smaller
    ASSERT_EQ(ours, lcmEncoding(ws)) << "round " << round;
  }
}

TEST(WorldStateEncoding, RefusesAStringHoldingANulAsBusEncodeDoes) {
  // LCM sizes such a string by size() but writes it up to the NUL: its encode() comes out shorter than
  // getEncodedSize(), which Bus::encode reports as an error. encodeWorldState throws likewise.
  world_state_t ws{};
  ws.robot.name = "robot";
  ws.agents.resize(1);
  ws.agents[0].name = "a";
  ws.num_agents = 1;
  std::vector<std::uint8_t> ours;
  encodeWorldState(ws, ours);
  EXPECT_EQ(ours, lcmEncoding(ws));
  // hash 8 + utime, tick, episode 24 + robot (175 fixed + "robot" 4 + 6 + "" 4 + 1) + num_agents 4 +
  // agent (175 + "a" 4 + 2 + "" 4 + 1) + num_collisions 4 = 416
  EXPECT_EQ(ours.size(), 416u);

  ws.agents[0].name = std::string("a\0b", 3);
  EXPECT_THROW(encodeWorldState(ws, ours), std::runtime_error);
  EXPECT_NE(ws.getEncodedSize(), ws.encode(ours.data(), 0, static_cast<int>(ours.size())));
}

// What the evaluator's worker does with the bytes of encodeWorldState (wire::readBody into one
// reused message, whose strings and arrays grow and shrink round after round): the message LCM's
// own decoder gives, field for field (compared through LCM's encoding: NaN bits included).
TEST(WorldStateEncoding, TheCodecReadsBackWhatLcmDecodes) {
  std::mt19937_64 rng(12);
  world_state_t decoded{};
  std::vector<std::uint8_t> ours;
  for (int round = 0; round < 200; ++round) {
    world_state_t ws{};
    ws.utime = static_cast<std::int64_t>(rng());
    ws.tick = round;
    ws.robot = randomAgent(rng);
    ws.agents.resize(rng() % 30);
    for (auto& a : ws.agents) a = randomAgent(rng);
    ws.num_agents = static_cast<std::int32_t>(ws.agents.size());
    encodeWorldState(ws, ours);
    wire::Reader r(ours.data() + 8);
    wire::readBody(r, decoded);
    ASSERT_EQ(r.position(), ours.data() + ours.size()) << "round " << round;
    world_state_t by_lcm{};
    ASSERT_EQ(by_lcm.decode(ours.data(), 0, static_cast<int>(ours.size())), static_cast<int>(ours.size()));
    ASSERT_EQ(lcmEncoding(decoded), lcmEncoding(by_lcm)) << "round " << round;
    ASSERT_EQ(decoded.agents.size(), by_lcm.agents.size());
  }
}

// The codec is generated for every type of lcmtypes/: arrays of strings, doubles, bytes and floats
// sized by a count field come out as LCM's encode() writes them, and read back the same.
TEST(WireCodec, EveryKindOfFieldIsLcmsEncodingByteForByte) {
  live_metrics_t live{};
  live.utime = 123456789;
  live.episode = 7;
  live.names = {"completed", "", "time_to_reach_goal"};
  live.values = {1.0, -0.0, std::numeric_limits<double>::quiet_NaN()};
  live.num_metrics = 3;
  EXPECT_EQ(codecEncoding(live), lcmEncoding(live));

  map_t map{};
  map.episode = 2;
  map.seq = 1;
  map.scenario = "cafe";
  map.resolution = 0.05;
  map.origin_x = -12.5;
  map.width = 3;
  map.height = 2;
  map.cells = {0, 100, -1, 0, 0, 100};
  map.num_cells = 6;
  EXPECT_EQ(codecEncoding(map), lcmEncoding(map));

  laser_scan_t scan{};
  scan.utime = 5;
  scan.ranges = {0.5f, std::numeric_limits<float>::infinity(), 3.25f};
  scan.num_ranges = 3;
  EXPECT_EQ(codecEncoding(scan), lcmEncoding(scan));

  const std::vector<std::uint8_t> bytes = lcmEncoding(live);
  live_metrics_t back{};
  back.names = {"a longer name than any of these", "x", "y", "z"};  // more, and longer: replaced
  wire::Reader r(bytes.data() + 8);
  wire::readBody(r, back);
  EXPECT_EQ(back.names, live.names);
  EXPECT_EQ(lcmEncoding(back), bytes);
}

// readFields<Keep> reads what Keep names as readBody does, steps over the rest (strings, nested
// messages, arrays of messages) and leaves those fields as they were; skipBody steps over a whole
// message. Both end where LCM's decoder ends.
TEST(WireCodec, ReadFieldsReadsWhatItNamesAndStepsOverTheRest) {
  using Keep = wire::Fields<&world_state_t::agents, &agent_state_t::id, &agent_state_t::name, &agent_state_t::y,
                            &agent_state_t::obstacles, &point2d_t::x>;
  std::mt19937_64 rng(13);
  std::vector<std::uint8_t> ours;
  world_state_t partial{};
  for (int round = 0; round < 100; ++round) {
    world_state_t ws{};
    ws.tick = round;
    ws.robot = randomAgent(rng);
    ws.agents.resize(rng() % 30);
    for (auto& a : ws.agents) a = randomAgent(rng);
    ws.num_agents = static_cast<std::int32_t>(ws.agents.size());
    ws.collisions.resize(rng() % 3);
    ws.num_collisions = static_cast<std::int32_t>(ws.collisions.size());
    encodeWorldState(ws, ours);

    partial.tick = -1;
    partial.robot.id = -7;
    const std::size_t before = partial.agents.size();
    for (auto& a : partial.agents) {  // what the previous round left: only what Keep names changes
      a.x = 0.5;
      a.behavior_tree = "left";
    }
    wire::Reader r(ours.data() + 8);
    wire::readFields<Keep>(r, partial);
    ASSERT_EQ(r.position(), ours.data() + ours.size()) << "round " << round;
    EXPECT_EQ(partial.tick, -1);                           // not named
    EXPECT_EQ(partial.robot.id, -7);                       // the robot is not named: stepped over whole
    EXPECT_EQ(partial.num_collisions, ws.num_collisions);  // a count is always read
    EXPECT_TRUE(partial.collisions.empty());
    ASSERT_EQ(partial.agents.size(), ws.agents.size());
    for (std::size_t i = 0; i < ws.agents.size(); ++i) {
      const agent_state_t& got = partial.agents[i];
      const agent_state_t& want = ws.agents[i];
      EXPECT_EQ(got.id, want.id);
      EXPECT_EQ(got.name, want.name);
      EXPECT_EQ(std::memcmp(&got.y, &want.y, sizeof got.y), 0);  // NaN bits included
      if (i < before) {                                          // not named: as the previous round left them
        EXPECT_EQ(got.x, 0.5);
        EXPECT_EQ(got.behavior_tree, "left");
      }
      EXPECT_EQ(got.num_goals, want.num_goals);  // the count, not the goals
      ASSERT_EQ(got.obstacles.size(), want.obstacles.size());
      for (std::size_t k = 0; k < want.obstacles.size(); ++k)
        EXPECT_EQ(std::memcmp(&got.obstacles[k].x, &want.obstacles[k].x, sizeof(double)), 0);
    }

    wire::Reader skipper(ours.data() + 8);
    wire::skipBody(skipper, wire::Type<world_state_t>{});
    EXPECT_EQ(skipper.position(), ours.data() + ours.size()) << "round " << round;
  }

  // Arrays of strings and of bytes, stepped over and read.
  live_metrics_t live{};
  live.names = {"completed", "", "time_to_reach_goal"};
  live.values = {1.0, 2.0, 3.0};
  live.num_metrics = 3;
  const std::vector<std::uint8_t> bytes = lcmEncoding(live);
  live_metrics_t back{};
  wire::Reader r(bytes.data() + 8);
  wire::readFields<wire::Fields<&live_metrics_t::values>>(r, back);
  EXPECT_EQ(r.position(), bytes.data() + bytes.size());
  EXPECT_TRUE(back.names.empty());
  EXPECT_EQ(back.values, live.values);
  map_t map{};
  map.cells = {0, 100, -1};
  map.num_cells = 3;
  const std::vector<std::uint8_t> map_bytes = lcmEncoding(map);
  wire::Reader map_reader(map_bytes.data() + 8);
  wire::skipBody(map_reader, wire::Type<map_t>{});
  EXPECT_EQ(map_reader.position(), map_bytes.data() + map_bytes.size());
}
