#include "hunav/manager/manager_node.hpp"

#include "hunav/channels.hpp"
#include "hunav/message_checks.hpp"

namespace hunav::manager {

ManagerNode::ManagerNode(Bus& bus, bool count_episodes) : bus_(bus) {
  bus_.subscribe<step_request_t>(channels::kStepRequest, [this](const step_request_t& r) { onRequest(r); });
  if (count_episodes)
    bus_.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& e) {
      if (e.event == episode_event_t::END) ++episodes_ended_;
    });
}

void ManagerNode::onRequest(const step_request_t& request) {
  checkFinite(request.dt, "dt", "step request");
  if (request.dt < 0.0 || request.dt > 1.0) throw BadMessage("step request: dt out of range");
  checkAgentStates(request.agents, request.num_agents, "step request");
  checkAgentState(request.robot, "step request robot");

  if (have_last_ && request.episode == last_reply_.episode) {
    if (request.seq == last_reply_.seq) {  // a resend: the answer to a seq never changes
      ++replies_resent_;
      bus_.publish(channels::kStepReply, last_reply_);
      return;
    }
    if (request.seq < last_reply_.seq) return;  // stale duplicate, already answered
  }
  have_last_ = false;  // until the new reply is complete
  manager_.step(request, last_reply_);  // reuses the last reply's storage
  have_last_ = true;
  ++steps_computed_;
  bus_.publish(channels::kStepReply, last_reply_);
}

}  // namespace hunav::manager
