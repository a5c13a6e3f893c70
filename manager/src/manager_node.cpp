#include "hunav/manager/manager_node.hpp"

#include "hunav/channels.hpp"
#include "hunav/message_checks.hpp"

namespace hunav::manager {

ManagerNode::ManagerNode(Bus& bus, bool count_episodes) : bus_(bus) {
  request_drops_ =
      &bus_.subscribe<step_request_t>(channels::kStepRequest, [this](const step_request_t& r) { onRequest(r); });
  if (count_episodes)
    event_drops_ = &bus_.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& e) {
      if (e.event == episode_event_t::END) ++episodes_ended_;
    });
}

std::uint64_t ManagerNode::droppedMessages() const {
  return request_drops_->count + (event_drops_ != nullptr ? event_drops_->count : 0) + bus_.malformedDatagrams();
}

void ManagerNode::onRequest(const step_request_t& request) {
  checkFinite(request.dt, "dt", "step request");
  if (request.dt < 0.0 || request.dt > 1.0) throw BadMessage("step request: dt out of range");
  checkAgentStates(request.agents, request.num_agents, "step request");
  checkAgentState(request.robot, "step request robot");

  if (have_answered_ && request.episode == answered_episode_) {
    if (request.seq == answered_seq_) {  // a resend: the answer to a seq never changes
      ++replies_resent_;
      // Without the reply kept, it went into the in-process queue itself, where nothing loses it:
      // the world has it already or gets it next.
      if (have_last_) bus_.publish(channels::kStepReply, last_reply_);
      return;
    }
    if (request.seq < answered_seq_) return;  // stale duplicate, already answered
  }
  have_answered_ = have_last_ = false;  // until the new reply is complete
  manager_.step(request, last_reply_);  // reuses the last reply's storage
  last_reply_.dropped_messages = static_cast<std::int64_t>(droppedMessages());
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
  if (!bus_.inProcess()) {
    bus_.publish(channels::kStepReply, last_reply_);  // encoded: the reply stays here for resends
    have_last_ = true;
    return;
  }
  // In process the reply is handed over, not copied (1000 people: a copy of every string and point
  // list of the crowd per step); last_reply_ gets a recycled message whose arrays the next step
  // reuses. A reply the loss-test hook drops is left untouched (and kept for the resend).
  const std::uint64_t lost_before = bus_.lostForTesting();
  bus_.publish(channels::kStepReply, std::move(last_reply_));
  have_last_ = bus_.lostForTesting() != lost_before;
}

}  // namespace hunav::manager
