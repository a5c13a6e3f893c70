#pragma once
// The manager process logic: answers STEP_REQUEST with STEP_REPLY. Each reply carries the
// messages the node dropped so far (the world puts the episode's share into its END event). A step
// request more than kMaxSeqAhead (message_checks.hpp) ahead of the last answered of its episode, and
// an END of an episode it neither heard start nor answered, are not the world's: dropped and counted.
#include <cstdint>
#include <hunav/episode_event_t.hpp>
#include <optional>
#include <vector>

#include "hunav/bus.hpp"
#include "hunav/manager/agent_manager.hpp"

namespace hunav::manager {

class ManagerNode {
 public:
  // count_episodes: listen to EPISODE_EVENT to count ended episodes (episodesEnded()). Without it the
  // manager hears only STEP_REQUEST: with channel_ports=1 (channels.hpp) it then opens no receive
  // socket on the URL's port, where every WORLD_STATE would otherwise wake it each tick.
  // threads: the process's pool for large crowds (AgentManager); null: none.
  explicit ManagerNode(Bus& bus, ThreadPool* threads = nullptr, bool count_episodes = true);

  AgentManager& manager() { return manager_; }
  std::uint64_t stepsComputed() const { return steps_computed_; }
  std::uint64_t repliesResent() const { return replies_resent_; }
  std::uint64_t episodesEnded() const { return episodes_ended_; }
  // The step requests it dropped (undecodable, or rejected: bad numbers, a behavior tree that is not
  // one of its own) and why the last one was.
  SubscriptionDrops requestDrops() const { return request_sub_.drops(); }
  // Everything it dropped: step requests, events, and (on a socket bus) malformed datagrams.
  std::uint64_t droppedMessages() const;

 private:
  void onRequest(const step_request_t& request);
  void onEvent(const episode_event_t& e);

  Bus& bus_;
  AgentManager manager_;
  bool have_answered_ = false;  // answered_seq_ and answered_episode_ are set
  std::int64_t answered_seq_ = 0;
  std::int64_t answered_episode_ = 0;
  step_reply_t last_reply_;           // the answer to answered_seq_, kept for resends
  people_social_t social_;            // PEOPLE_SOCIAL, reused
  std::vector<int32_t> request_ids_;  // checkAgentStates' sort, for a request out of id order
  std::uint64_t steps_computed_ = 0;
  std::uint64_t replies_resent_ = 0;
  std::uint64_t episodes_ended_ = 0;
  std::optional<std::int64_t> started_episode_;  // of the last START heard (count_episodes)
  std::optional<std::int64_t> ended_episode_;    // of the last END counted
  // Last, so that they end first (the handlers use the members above).
  Subscription request_sub_;
  Subscription event_sub_;  // with count_episodes
};

}  // namespace hunav::manager
