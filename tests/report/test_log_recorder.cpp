// LogRecorder over several LCM instances (one per port with channel_ports=1): every message of every
// instance lands in the one log, each channel in its order, stamped with its simulation time.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <hunav/world_state_t.hpp>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "hunav/report/log_recorder.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace {

struct Event {
  std::string channel;
  std::int64_t stamp;
};

std::vector<Event> readLog(const std::string& path) {
  std::vector<Event> events;
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good()) << "cannot read " << path;
  while (const lcm::LogEvent* ev = log.readNextEvent()) events.push_back({ev->channel, ev->timestamp});
  return events;
}

// Handles until `count` events are written, at most 200 handle calls of up to 100 ms each.
void recordUntil(hunav::report::LogRecorder& recorder, std::int64_t count) {
  for (int i = 0; i < 200 && recorder.events() < count; ++i) recorder.handle(std::chrono::milliseconds(100));
}

TEST(LogRecorder, RecordsEveryInstanceIntoOneLog) {
  // memq:// instances are separate buses, as the ports of channel_ports=1 are.
  lcm::LCM main_port("memq://"), request_port("memq://"), reply_port("memq://");
  const std::string path = (hunav::testing::testDir() / "recorded.lcmlog").string();
  {
    hunav::report::LogRecorder recorder({&main_port, &request_port, &reply_port}, path);
    // Two ticks: request (utime t), reply (t + dt), world state (t + dt), as a lockstep run sends them.
    for (std::int64_t t : {0, 10000}) {
      hunav::step_request_t request{};
      request.utime = t;
      request_port.publish("STEP_REQUEST", &request);
      recordUntil(recorder, recorder.events() + 1);
      hunav::step_reply_t reply{};
      reply.utime = t + 10000;
      reply_port.publish("STEP_REPLY", &reply);
      recordUntil(recorder, recorder.events() + 1);
      hunav::world_state_t state{};
      state.utime = t + 10000;
      main_port.publish("WORLD_STATE", &state);
      recordUntil(recorder, recorder.events() + 1);
    }
    ASSERT_EQ(recorder.events(), 6);
    EXPECT_EQ(recorder.eventsPerChannel().at("STEP_REQUEST"), 2);
    EXPECT_EQ(recorder.eventsPerChannel().at("STEP_REPLY"), 2);
    EXPECT_EQ(recorder.eventsPerChannel().at("WORLD_STATE"), 2);
    recorder.flush();
  }
  const std::vector<Event> events = readLog(path);
  ASSERT_EQ(events.size(), 6u);
  // Handled one at a time, so in the order sent; stamps are the messages' utimes.
  const std::vector<std::string> channels = {"STEP_REQUEST", "STEP_REPLY", "WORLD_STATE",
                                             "STEP_REQUEST", "STEP_REPLY", "WORLD_STATE"};
  const std::vector<std::int64_t> stamps = {0, 10000, 10000, 10000, 20000, 20000};
  for (std::size_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].channel, channels[i]) << "event " << i;
    EXPECT_EQ(events[i].stamp, stamps[i]) << "event " << i;
  }
}

TEST(LogRecorder, TimesOutWhenNoInstanceHasAMessage) {
  lcm::LCM a("memq://"), b("memq://");
  const std::string path = (hunav::testing::testDir() / "quiet.lcmlog").string();
  hunav::report::LogRecorder recorder({&a, &b}, path);
  EXPECT_FALSE(recorder.handle(std::chrono::milliseconds(10)));
  EXPECT_EQ(recorder.events(), 0);
}

TEST(LogRecorder, AChannelExpressionLcmCannotCompileIsRejectedNotFatal) {
  // LCM's C++ subscribe() hands back a subscription holding NULL for such an expression, which
  // crashes on its first use; the recorder says what is wrong instead.
  lcm::LCM a("memq://"), b("memq://");
  const std::string path = (hunav::testing::testDir() / "regex.lcmlog").string();
  for (const char* bad : {"(", "[z-a]"}) {
    try {
      hunav::report::LogRecorder recorder({&a, &b}, path, bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
  // The instances are left usable: a recorder with a good expression records on them.
  hunav::report::LogRecorder recorder({&a, &b}, path, "WORLD_.*");
  EXPECT_FALSE(recorder.handle(std::chrono::milliseconds(1)));
}

}  // namespace
