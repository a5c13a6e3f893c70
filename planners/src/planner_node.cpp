#include "hunav/planners/planner_node.hpp"

#include <cmath>
#include <string>

#include "hunav/channels.hpp"
#include "hunav/message_checks.hpp"

namespace hunav::planners {

namespace {
void requireFinite(double value, const char* field) {
  if (!std::isfinite(value)) throw BadMessage(std::string("robot_observation_t: non-finite ") + field);
}
void require(bool condition, const char* what) {
  if (!condition) throw BadMessage(std::string("robot_observation_t: ") + what);
}
}  // namespace

PlannerNode::PlannerNode(Bus& bus, std::unique_ptr<Planner> planner, std::string name)
    : bus_(bus), planner_(std::move(planner)), name_(std::move(name)) {
  observation_sub_ = bus_.subscribe<robot_observation_t>(
      channels::kRobotObservation, [this](const robot_observation_t& obs) { onObservation(obs); });
  event_sub_ =
      bus_.subscribe<episode_event_t>(channels::kEpisodeEvent, [this](const episode_event_t& e) { onEpisodeEvent(e); });
}

std::uint64_t PlannerNode::droppedMessages() const {
  return observation_sub_.droppedCount() + event_sub_.droppedCount() + bus_.malformedDatagrams() + forged_dropped_;
}

void PlannerNode::announce() {
  planner_ready_t ready{};
  ready.name = name_;
  dropped_announced_ = droppedMessages();
  ready.dropped_messages = saturatedCount(dropped_announced_);
  bus_.publish(channels::kPlannerReady, ready);
}

void PlannerNode::announceNewDrops() {
  if (droppedMessages() != dropped_announced_) announce();
}

void PlannerNode::validate(const robot_observation_t& obs) {
  const double state[] = {obs.x,     obs.y,     obs.yaw,   obs.v,         obs.w,         obs.radius,
                          obs.max_v, obs.min_v, obs.max_w, obs.max_acc_v, obs.max_acc_w, obs.control_period};
  for (double value : state) requireFinite(value, "robot state or limits");
  require(obs.radius > 0.0, "radius must be > 0");
  require(obs.min_v <= obs.max_v && obs.max_v >= 0.0, "needs min_v <= max_v and max_v >= 0");
  require(obs.max_w >= 0.0 && obs.max_acc_v > 0.0 && obs.max_acc_w > 0.0, "needs max_w >= 0 and accelerations > 0");
  require(obs.control_period > 0.0, "control_period must be > 0");
  if (obs.goal.valid) {
    for (double value : {obs.goal.x, obs.goal.y, obs.goal.yaw, obs.goal.radius}) requireFinite(value, "goal");
    require(obs.goal.radius >= 0.0, "goal radius must be >= 0");
  }

  const laser_scan_t& scan = obs.scan;
  require(scan.num_ranges >= 0 && scan.num_ranges <= kMaxRanges, "num_ranges out of range");
  for (double value : {scan.sensor_x, scan.sensor_y, scan.sensor_yaw, scan.angle_min, scan.angle_increment,
                       scan.range_min, scan.range_max})
    requireFinite(value, "scan geometry");
  for (float r : scan.ranges) requireFinite(r, "scan range");

  require(obs.num_people >= 0 && obs.num_people <= kMaxPeople, "num_people out of range");
  for (const detected_person_t& p : obs.people) {
    for (double value : {p.x, p.y, p.yaw, p.vx, p.vy, p.radius}) requireFinite(value, "person");
    require(p.radius >= 0.0, "person radius must be >= 0");
  }
}

void PlannerNode::beginEpisode(std::int64_t episode, bool announced) {
  planner_->reset();
  episode_ = episode;
  episode_announced_ = announced;
  episode_ended_ = false;
  episode_confirmed_ = false;
  discardPendingStart();
  last_reply_.reset();
}

void PlannerNode::discardPendingStart() {
  if (pending_start_) ++forged_dropped_;  // no observation of its episode came: not the world's
  pending_start_.reset();
}

void PlannerNode::onObservation(const robot_observation_t& obs) {
  announceNewDrops();  // before the command: the world has the count by the time it answers
  validate(obs);
  if (!episode_ || (episode_ended_ && obs.episode != *episode_)) {
    beginEpisode(obs.episode, false);  // the first, or the next episode whose START was lost
  } else if (obs.episode == *episode_) {
    discardPendingStart();  // the world sends nothing of this episode after another's START
  } else {
    // A START that no observation of its episode followed was not the world's: the observations decide.
    const bool unconfirmed_start = episode_announced_ && !episode_confirmed_;
    if (unconfirmed_start) ++forged_dropped_;
    if (pending_start_ && obs.episode == *pending_start_) {
      pending_start_.reset();
      beginEpisode(obs.episode, true);  // the START heard during the last episode was the world's
    } else if (!episode_announced_ || unconfirmed_start) {
      beginEpisode(obs.episode, false);  // joined mid-episode: the world's numbers are all it knows
    } else {
      throw BadMessage("robot_observation_t: episode " + std::to_string(obs.episode) + " during episode " +
                       std::to_string(*episode_) + " (whose START was heard)");
    }
  }
  // The sequence number: the world's next is the last answered's or one more (lockstep); far ahead of
  // it, an observation cannot be the world's, and answering it would make every real one look stale.
  const std::int64_t base = last_reply_ ? last_reply_->seq : episode_announced_ ? 0 : -1;
  if (base >= 0 && obs.seq > base && obs.seq - base > kMaxSeqAhead)
    throw BadMessage("robot_observation_t: seq " + std::to_string(obs.seq) + " is more than " +
                     std::to_string(kMaxSeqAhead) + " ahead of " + std::to_string(base));
  episode_confirmed_ = true;
  if (last_reply_) {
    if (obs.seq == last_reply_->seq) {  // a resend: same answer, no replanning
      bus_.publish(channels::kRobotCommand, *last_reply_);
      ++commands_sent_;
      ++replies_resent_;
      return;
    }
    if (obs.seq < last_reply_->seq) {  // a late duplicate of an observation already overtaken
      ++stale_ignored_;
      return;
    }
  }
  robot_command_t cmd = planner_->plan(obs);
  ++plans_computed_;
  cmd.utime = obs.utime;
  cmd.seq = obs.seq;
  cmd.episode = obs.episode;
  last_reply_ = cmd;
  bus_.publish(channels::kRobotCommand, cmd);
  ++commands_sent_;
  publishPath(obs);
}

void PlannerNode::publishPath(const robot_observation_t& obs) {
  // After the command, so the world never waits for it; a message only monitors read.
  const std::vector<Vec2>* path = planner_->plannedPath();
  if (path == nullptr) return;
  const std::vector<Vec2>& points = *path;
  path_msg_.utime = obs.utime;
  path_msg_.seq = obs.seq;
  path_msg_.episode = obs.episode;
  path_msg_.num_points = static_cast<std::int32_t>(points.size());
  path_msg_.points.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    path_msg_.points[i].x = points[i].x();
    path_msg_.points[i].y = points[i].y();
  }
  bus_.publish(channels::kRobotPath, path_msg_);
}

void PlannerNode::onEpisodeEvent(const episode_event_t& event) {
  checkEpisodeEventText(event);
  if (event.event == episode_event_t::START) {
    if (!episode_ || episode_ended_) {
      // A restarted world may reuse an episode number: after an END, any START begins afresh.
      beginEpisode(event.episode, true);
    } else if (!episode_confirmed_) {
      // Two STARTs and no observation yet (one may be forged): the first observation picks its episode.
      if (event.episode != *episode_) {
        discardPendingStart();
        pending_start_ = event.episode;
      }
    } else if (event.episode == *episode_ + 1) {
      // While an episode runs, the next one's START waits for an observation of its episode (the
      // END of the running one was lost) instead of ending it: a forged one never gets one.
      discardPendingStart();
      pending_start_ = event.episode;
    } else if (event.episode != *episode_) {
      throw BadMessage("episode_event_t: START of episode " + std::to_string(event.episode) + " during episode " +
                       std::to_string(*episode_));
    }
    announce();  // so a world hears the count in every mode (in process nothing else announces)
  } else if (event.event == episode_event_t::END) {
    if (!episode_ || event.episode != *episode_) {
      throw BadMessage("episode_event_t: END of episode " + std::to_string(event.episode) +
                       (episode_ ? ", not the one being served (" + std::to_string(*episode_) + ")"
                                 : std::string(" before any episode")));
    } else if (episode_ended_) {
      return;  // a repeated END
    } else if (!episode_confirmed_) {
      // START and END with no observation between: a forged pair would end `--episodes N` early.
      throw BadMessage("episode_event_t: END of episode " + std::to_string(event.episode) +
                       ", none of whose observations came");
    }
    discardPendingStart();
    episode_ended_ = true;
    ++episodes_ended_;
  } else {
    throw BadMessage("episode_event_t: unknown event " + std::to_string(event.event));
  }
}

}  // namespace hunav::planners
