#pragma once
// Messages that do not belong to the run they reach (issue 31), forged from what the run sends: each
// kind that ended a lockstep run before (an END or START of another episode, an observation with a
// seq of 10^12, a 10,000-byte mode of invalid UTF-8, a PLANNER_READY count of 4.6e18) and their
// relatives (observations of another episode, step requests far ahead, commands and replies to
// requests never sent). Used by the in-process property test (test_forged_messages.cpp) and by the
// forger that injects them into a lockstep run in a private network namespace (forge_messages.cpp).
#include <array>
#include <cstdint>
#include <hunav/episode_event_t.hpp>
#include <hunav/planner_ready_t.hpp>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <hunav/world_state_t.hpp>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "hunav/bus.hpp"
#include "hunav/channels.hpp"
#include "hunav/message_checks.hpp"

namespace hunav::testing {

enum class Forgery {
  EndOfAnotherEpisode,
  StartOfAnotherEpisode,
  ObservationFarAhead,
  ObservationOfAnotherEpisode,
  StepRequestFarAhead,
  EventWithBadText,
  ReadyWithBadCount,
  CommandAhead,
  ReplyAhead,
};
inline constexpr int kForgeryKinds = 9;

inline const char* forgeryName(Forgery f) {
  static const char* names[kForgeryKinds] = {
      "END of another episode",         "START of another episode",   "observation far ahead",
      "observation of another episode", "step request far ahead",     "event with bad text",
      "PLANNER_READY with a bad count", "command ahead of the world", "step reply ahead of the world"};
  return names[static_cast<int>(f)];
}

class Forger {
 public:
  // Learns the run's episode from its world states (only the world sends those) and keeps the last
  // real observation and step request (its own forgeries are told apart: another episode or a seq
  // far ahead), to forge from.
  Forger(Bus& bus, std::uint64_t seed) : bus_(bus), rng_(seed) {
    subs_.push_back(bus_.subscribe<world_state_t>(channels::kWorldState,
                                                  [this](const world_state_t& ws) { episode_ = ws.episode; }));
    subs_.push_back(
        bus_.subscribe<robot_observation_t>(channels::kRobotObservation, [this](const robot_observation_t& o) {
          if (episode_ && o.episode == *episode_ && (!obs_ || o.seq <= obs_->seq + 10)) obs_ = o;
        }));
    subs_.push_back(bus_.subscribe<step_request_t>(channels::kStepRequest, [this](const step_request_t& r) {
      if (episode_ && r.episode == *episode_ && (!request_ || r.seq <= request_->seq + 10)) request_ = r;
    }));
  }

  // Publishes one forged message of a random kind (one it can forge from what it heard so far);
  // returns its kind, or nothing before the run's first world state.
  std::optional<Forgery> forgeOne() {
    if (!episode_) return std::nullopt;
    for (;;) {
      const auto kind = static_cast<Forgery>(pick(0, kForgeryKinds - 1));
      if (publish(kind)) {
        ++counts_[static_cast<int>(kind)];
        return kind;
      }
    }
  }
  const std::array<int, kForgeryKinds>& counts() const { return counts_; }

 private:
  std::int64_t pick(std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng_);
  }
  // Another episode than the run's. Never the next one for an observation: a START of the next episode
  // followed by its observations before the world's next one is the world's own sequence when its END
  // is lost (the planner takes it up), which no check can tell from a forgery.
  std::int64_t otherEpisode(bool for_observation = false) {
    const std::int64_t e = *episode_;
    return pick(0, 1) == 0 ? e + pick(for_observation ? 2 : 1, 1000) : e - pick(1, 1000);
  }
  // Beyond the bound even when what the forger heard last is a few requests behind the receiver.
  std::int64_t farAhead(std::int64_t seq) {
    return pick(0, 1) == 0 ? seq + kMaxSeqAhead + pick(100, 1000) : std::int64_t{1'000'000'000'000} + pick(0, 1000);
  }
  episode_event_t event(std::int8_t kind, std::int64_t episode) {
    episode_event_t e{};
    e.utime = obs_ ? obs_->utime : 0;
    e.event = kind;
    e.episode = episode;
    e.run_id = "forged";
    e.scenario = "forged";
    e.planner = "dwb";
    e.mode = "lockstep";
    e.status = kind == episode_event_t::START ? "running" : "goal_reached";
    e.reason = "forged";
    e.fingerprint = "0123456789abcdef";
    e.manager_dropped_messages = e.planner_dropped_messages = -1;
    return e;
  }

  bool publish(Forgery kind) {
    switch (kind) {
      case Forgery::EndOfAnotherEpisode:
        bus_.publish(channels::kEpisodeEvent, event(episode_event_t::END, otherEpisode()));
        return true;
      case Forgery::StartOfAnotherEpisode:
        bus_.publish(channels::kEpisodeEvent, event(episode_event_t::START, otherEpisode()));
        return true;
      case Forgery::ObservationFarAhead: {
        if (!obs_) return false;
        robot_observation_t o = *obs_;
        o.seq = farAhead(o.seq);
        bus_.publish(channels::kRobotObservation, o);
        return true;
      }
      case Forgery::ObservationOfAnotherEpisode: {
        if (!obs_) return false;
        robot_observation_t o = *obs_;
        o.episode = otherEpisode(true);
        o.seq = pick(1, 100000);
        bus_.publish(channels::kRobotObservation, o);
        return true;
      }
      case Forgery::StepRequestFarAhead: {
        if (!request_) return false;
        step_request_t r = *request_;
        r.seq = farAhead(r.seq);
        bus_.publish(channels::kStepRequest, r);
        return true;
      }
      case Forgery::EventWithBadText: {
        // Of the run's own episode: only its text can tell it apart.
        episode_event_t e = event(pick(0, 1) == 0 ? episode_event_t::START : episode_event_t::END, *episode_);
        std::string& field = pick(0, 1) == 0 ? e.mode : e.status;
        field = pick(0, 1) == 0 ? std::string(10000, '\xff') : std::string(kMaxTextBytes + 1, 'a');
        bus_.publish(channels::kEpisodeEvent, e);
        return true;
      }
      case Forgery::ReadyWithBadCount: {
        planner_ready_t r{};
        r.name = "dwb";
        r.dropped_messages = pick(0, 1) == 0 ? std::int64_t{4'600'000'000'000'000'000} : -pick(1, 1000);
        bus_.publish(channels::kPlannerReady, r);
        return true;
      }
      case Forgery::CommandAhead: {
        if (!obs_) return false;
        robot_command_t c{};
        c.utime = obs_->utime;
        c.episode = pick(0, 1) == 0 ? *episode_ : *episode_ + pick(1, 1000);
        // Far enough ahead that the world cannot have sent that observation by the time it arrives.
        c.seq = obs_->seq + 1000 + pick(0, 1000);
        c.v = 1.0;
        c.w = 1.0;
        bus_.publish(channels::kRobotCommand, c);
        return true;
      }
      case Forgery::ReplyAhead: {
        if (!request_) return false;
        step_reply_t r{};
        r.utime = request_->utime;
        r.episode = *episode_;
        r.seq = request_->seq + 1000 + pick(0, 1000);
        bus_.publish(channels::kStepReply, r);
        return true;
      }
    }
    return false;
  }

  Bus& bus_;
  std::mt19937_64 rng_;
  std::optional<std::int64_t> episode_;
  std::optional<robot_observation_t> obs_;
  std::optional<step_request_t> request_;
  std::array<int, kForgeryKinds> counts_{};
  std::vector<Subscription> subs_;
};

}  // namespace hunav::testing
