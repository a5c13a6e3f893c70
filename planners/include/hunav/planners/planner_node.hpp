#pragma once
// The planner process logic on the bus: answers each ROBOT_OBSERVATION with a ROBOT_COMMAND that
// echoes its utime, seq and episode (docs/planner_contract.md).
//  - Replies are idempotent: an observation with the (episode, seq) answered last gets the same
//    command again without replanning (the world resends on timeout). Older seqs are ignored.
//  - A new episode (in an EPISODE_EVENT START, or an observation when none runs) resets the planner.
//  - Invalid observations (non-finite numbers, impossible sizes or limits) are dropped and counted
//    by the Bus (BadMessage).
//  - Messages that do not fit the world's sequence cannot steer it (a forged or a foreign one), and
//    are dropped and counted: an END of another episode than the one served; an observation of
//    another episode while one whose START was heard runs; an observation more than kMaxSeqAhead
//    (message_checks.hpp)
//    seqs ahead of the last answered (or of 0 after START). While an episode runs, a START of the next
//    one (the world counts episodes up from 1) waits for an observation of its episode (the END was
//    lost: the world sends nothing more of the running one) and is dropped when an observation of the
//    running episode, its END or another START comes first; a START of any other episode is dropped.
//    Event strings must pass checkEpisodeEventText().
//  - EPISODE_EVENT END events are counted, so the process can stop after N episodes.
//  - It announces itself on PLANNER_READY (planner_ready_t with its drop count) at each START and
//    whenever its drop count grew; a process repeats announce() as its heartbeat (planners/main.cpp).
//  - With each command of a planner that keeps a global path (dwb, scl, sfw), the path goes out on
//    ROBOT_PATH (planned_path_t) for monitors such as hunav_view; nobody in the step protocol reads it.
#include <cstdint>
#include <hunav/episode_event_t.hpp>
#include <hunav/planned_path_t.hpp>
#include <hunav/planner_ready_t.hpp>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <memory>
#include <optional>
#include <string>

#include "hunav/bus.hpp"
#include "hunav/planners/planner.hpp"

namespace hunav::planners {

class PlannerNode {
 public:
  static constexpr int kMaxRanges = 100000;  // the scenario loader's limit on laser beams
  static constexpr int kMaxPeople = 10000;

  // Subscribes ROBOT_OBSERVATION and EPISODE_EVENT on `bus` (which must outlive the node); `name`
  // goes into its PLANNER_READY announcements.
  PlannerNode(Bus& bus, std::unique_ptr<Planner> planner, std::string name = "");

  // Publishes planner_ready_t on PLANNER_READY: the name and droppedMessages().
  void announce();
  // Messages this node dropped since it was created: observations and events it rejected or could
  // not decode, and (on a socket bus) malformed datagrams.
  std::uint64_t droppedMessages() const;
  // The observations it dropped (undecodable or rejected) and why the last one was.
  SubscriptionDrops observationDrops() const { return observation_sub_.drops(); }

  std::int64_t episodesEnded() const { return episodes_ended_; }
  std::uint64_t plansComputed() const { return plans_computed_; }
  std::uint64_t commandsSent() const { return commands_sent_; }    // resends included
  std::uint64_t repliesResent() const { return replies_resent_; }  // cached answers to resent observations
  std::uint64_t staleIgnored() const { return stale_ignored_; }    // observations older than the last answered
  Planner& planner() { return *planner_; }
  // Gives the planner back, to serve another node later (hunav_run --seeds keeps it between episodes);
  // this node must then be destroyed without handling another message.
  std::unique_ptr<Planner> releasePlanner() { return std::move(planner_); }

  // Throws BadMessage when the observation cannot be planned on.
  static void validate(const robot_observation_t& obs);

 private:
  void onObservation(const robot_observation_t& obs);
  void onEpisodeEvent(const episode_event_t& event);
  // `announced`: its START was heard (else the node joined it from an observation).
  void beginEpisode(std::int64_t episode, bool announced);
  void discardPendingStart();
  // Publishes the planner's global path on ROBOT_PATH, when it keeps one (after a fresh plan).
  void publishPath(const robot_observation_t& obs);
  // Announces again when the drop count grew since the last announcement (checked per message).
  void announceNewDrops();

  Bus& bus_;
  std::unique_ptr<Planner> planner_;
  std::string name_;
  std::uint64_t dropped_announced_ = 0;
  std::optional<std::int64_t> episode_;        // the episode being served
  bool episode_announced_ = false;             // its START was heard
  bool episode_ended_ = false;                 // its END event arrived
  bool episode_confirmed_ = false;             // an observation of it came (a START alone may be forged)
  std::optional<std::int64_t> pending_start_;  // another episode's START heard while it runs
  std::uint64_t forged_dropped_ = 0;           // pending STARTs that no observation confirmed
  std::optional<robot_command_t> last_reply_;
  planned_path_t path_msg_;  // reused: its array keeps its capacity
  std::int64_t episodes_ended_ = 0;
  std::uint64_t plans_computed_ = 0;
  std::uint64_t commands_sent_ = 0;
  std::uint64_t replies_resent_ = 0;
  std::uint64_t stale_ignored_ = 0;
  // Last, so that they end first (the handlers use the members above).
  Subscription observation_sub_;
  Subscription event_sub_;
};

}  // namespace hunav::planners
