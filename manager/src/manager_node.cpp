#include "hunav/manager/manager_node.hpp"

#include "hunav/channels.hpp"
#include "hunav/message_checks.hpp"

namespace hunav::manager {

ManagerNode::ManagerNode(Bus& bus, ThreadPool* threads, bool count_episodes) : bus_(bus), manager_(threads) {
  request_sub_ =
      bus_.subscribe<step_request_t>(channels::kStepRequest, [this](const step_request_t& r) { onRequest(r); });
  if (count_episodes)
    event_sub_ =
        bus_.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& e) { onEvent(e); });
}

std::uint64_t ManagerNode::droppedMessages() const {
  return request_sub_.droppedCount() + event_sub_.droppedCount() + bus_.malformedDatagrams();
}

void ManagerNode::onEvent(const episode_event_t& e) {
  checkEpisodeEventText(e);
  if (e.event == episode_event_t::START) {
    started_episode_ = e.episode;
  } else if (e.event == episode_event_t::END) {
    // Only the END of an episode it heard start or answered counts (a forged one would end the process).
    const bool known =
        (started_episode_ && *started_episode_ == e.episode) || (have_answered_ && answered_episode_ == e.episode);
    if (!known) throw BadMessage("episode_event_t: END of episode " + std::to_string(e.episode) + ", never heard of");
    if (ended_episode_ && *ended_episode_ == e.episode) return;  // a repeated END
    ended_episode_ = e.episode;
    ++episodes_ended_;
  }
}

void ManagerNode::onRequest(const step_request_t& request) {
  checkFinite(request.dt, "dt", "step request");
  if (request.dt < 0.0 || request.dt > 1.0) throw BadMessage("step request: dt out of range");
  checkAgentStates(request.agents, request.num_agents, "step request", request_ids_);
  checkAgentState(request.robot, "step request robot");

  if (have_answered_ && request.episode == answered_episode_) {
    if (request.seq > answered_seq_ && request.seq - answered_seq_ > kMaxSeqAhead)
      throw BadMessage("step request: seq " + std::to_string(request.seq) + " is more than " +
                       std::to_string(kMaxSeqAhead) + " ahead of " + std::to_string(answered_seq_));
    if (request.seq == answered_seq_) {  // a resend: the answer to a seq never changes
      ++replies_resent_;
      bus_.publish(channels::kStepReply, last_reply_);
      return;
    }
    if (request.seq < answered_seq_) return;  // stale duplicate, already answered
  }
  have_answered_ = false;               // until the new reply is complete
  manager_.step(request, last_reply_);  // reuses the last reply's storage
  last_reply_.dropped_messages = saturatedCount(droppedMessages());
  answered_seq_ = request.seq;
  answered_episode_ = request.episode;
  have_answered_ = true;
  ++steps_computed_;
  // Speaking, conversations and gaze, beside the reply (before it, so a listener has them by the
  // time the world state of this step is out); only while some tree uses those nodes.
  if (manager_.socialActive()) {
    manager_.socialState(social_);
    bus_.publish(channels::kPeopleSocial, social_);
  }
  // Published as a copy: the reply stays here for resends, whichever bus carries it.
  bus_.publish(channels::kStepReply, last_reply_);
}

}  // namespace hunav::manager
