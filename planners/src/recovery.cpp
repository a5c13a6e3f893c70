#include "recovery.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hunav::planners {

namespace {
constexpr std::array<RecoveryBehavior, 6> kSequence = {RecoveryBehavior::ClearAndReplan, RecoveryBehavior::Spin,
                                                       RecoveryBehavior::BackUp,         RecoveryBehavior::Wait,
                                                       RecoveryBehavior::Reroute,        RecoveryBehavior::GiveWay};
constexpr double kGiveWayArrived = 0.3;  // m from the give-way place that counts as there
constexpr double kSpinTolerance = 0.02;  // rad short of spin_angle that counts as done (the last cycle's braking)
// Recovery places kept (a robot stuck for a whole episode adds two per behaviour): the oldest go first.
constexpr std::size_t kMaxStuckPlaces = 64;
constexpr double kMinMotionTime = 0.1;  // s, shortest motion a safety check looks along
constexpr double kSpellEnd = 2.0;       // m nearer the goal (along the floor) that end a stuck spell
}  // namespace

const char* recoveryName(RecoveryBehavior behavior) {
  switch (behavior) {
    case RecoveryBehavior::None:
      return "none";
    case RecoveryBehavior::ClearAndReplan:
      return "clear_and_replan";
    case RecoveryBehavior::Spin:
      return "spin";
    case RecoveryBehavior::BackUp:
      return "back_up";
    case RecoveryBehavior::Wait:
      return "wait";
    case RecoveryBehavior::Reroute:
      return "reroute";
    case RecoveryBehavior::GiveWay:
      return "give_way";
  }
  return "?";
}

Recovery::Recovery(const RecoveryParams& params) : params_(params) {
  if (!(params_.progress_distance > 0.0) || !(params_.progress_timeout > 0.0) || !(params_.spin_speed > 0.0) ||
      !(params_.backup_speed > 0.0) || !(params_.time_allowance > 0.0))
    throw std::invalid_argument(
        "recovery: progress_distance, progress_timeout, the speeds and time_allowance must be > 0");
}

void Recovery::reset() {
  tracking_ = false;
  stuck_places_.clear();
  paused_at_.reset();
  next_ = 0;
  active_ = RecoveryBehavior::None;
  started_ = 0;
}

void Recovery::startTracking(const robot_observation_t& obs) {
  reset();
  tracking_ = true;
  goal_ = Vec2(obs.goal.x, obs.goal.y);
  anchor_ = Vec2(obs.x, obs.y);
  window_start_ = obs.utime;
  best_distance_ = std::numeric_limits<double>::infinity();
}

void Recovery::newWay(const robot_observation_t& obs, double goal_distance) {
  anchor_ = Vec2(obs.x, obs.y);
  best_distance_ = goal_distance;
  spell_distance_ = goal_distance;  // a stuck spell goes on, measured along the new way
}

bool Recovery::madeProgress(const Vec2& p, double goal_distance) const {
  if (std::isfinite(goal_distance) && std::isfinite(best_distance_))
    return goal_distance <= best_distance_ - params_.progress_distance;
  // No distance along the floor: moving away from where the robot was counts.
  const double d2 = params_.progress_distance * params_.progress_distance;
  if ((p - anchor_).squaredNorm() < d2) return false;
  return std::all_of(stuck_places_.begin(), stuck_places_.end(),
                     [&](const Vec2& place) { return (p - place).squaredNorm() >= d2; });
}

bool Recovery::applicable(RecoveryBehavior behavior, const robot_observation_t& obs) const {
  // A robot that may not reverse cannot back up: the world would clamp the command to min_v.
  if (behavior == RecoveryBehavior::BackUp) return obs.min_v < 0.0 && params_.backup_distance > 0.0;
  if (behavior == RecoveryBehavior::Reroute) return params_.block_time > 0.0;
  if (behavior == RecoveryBehavior::GiveWay) return params_.give_way_distance > 0.0;
  return true;
}

std::optional<Vec2> Recovery::giveWayTarget(const robot_observation_t& obs) {
  if (active_ != RecoveryBehavior::GiveWay || !give_way_target_ || give_way_at_) return std::nullopt;
  if ((Vec2(obs.x, obs.y) - *give_way_target_).norm() <= kGiveWayArrived || elapsed(obs) >= params_.time_allowance) {
    give_way_at_ = obs.utime;  // there (or out of time): it stands from now on
    return std::nullopt;
  }
  return give_way_target_;
}

RecoveryBehavior Recovery::update(const robot_observation_t& obs, double goal_distance) {
  const Vec2 p(obs.x, obs.y);
  // A new goal, or the clock went back (a new episode without reset()): track afresh.
  if (!tracking_ || Vec2(obs.goal.x, obs.goal.y) != goal_ || obs.utime < window_start_) startTracking(obs);
  if (!std::isfinite(best_distance_)) best_distance_ = goal_distance;  // the first distance known
  if (active_ != RecoveryBehavior::None) return active_;
  if (madeProgress(p, goal_distance)) {
    anchor_ = p;
    window_start_ = obs.utime;
    if (std::isfinite(goal_distance)) best_distance_ = goal_distance;
    // A stuck spell ends once the robot is kSpellEnd nearer than where it began: a robot that
    // edges forward through a crowd at a doorway stays impatient (section "While stuck").
    const bool spell_over = !std::isfinite(goal_distance) || !std::isfinite(spell_distance_) ||
                            goal_distance <= spell_distance_ - kSpellEnd;
    if (spell_over)
      stuck_places_.clear();
    else if (!paused_at_)
      paused_at_ = obs.utime;  // impatience holds while the robot progresses
    next_ = 0;                 // the next time the robot is stuck, the sequence starts over
    return RecoveryBehavior::None;
  }
  if (!params_.enabled || static_cast<double>(obs.utime - window_start_) * 1e-6 < params_.progress_timeout)
    return RecoveryBehavior::None;
  RecoveryBehavior behavior = kSequence[next_];
  next_ = (next_ + 1) % kSequence.size();
  while (!applicable(behavior, obs)) {  // the sequence always holds applicable ones (clear, wait)
    behavior = kSequence[next_];
    next_ = (next_ + 1) % kSequence.size();
  }
  start(behavior, obs);
  if (behavior == RecoveryBehavior::ClearAndReplan || behavior == RecoveryBehavior::Reroute) {
    finish(obs);  // the caller clears (and blocks the passage) now and plans normally
    return behavior;
  }
  return active_;
}

void Recovery::start(RecoveryBehavior behavior, const robot_observation_t& obs) {
  active_ = behavior;
  active_start_ = obs.utime;
  active_from_ = Vec2(obs.x, obs.y);
  last_yaw_ = obs.yaw;
  turned_ = 0.0;
  spin_side_ = 0;
  give_way_target_.reset();
  give_way_at_.reset();
  ++started_;
  if (stuck_places_.empty()) {
    stuck_start_ = obs.utime;
    spell_distance_ = best_distance_;
    paused_at_.reset();
  } else if (paused_at_) {
    stuck_start_ += obs.utime - *paused_at_;  // stuck again: impatience grows on from where it held
    paused_at_.reset();
  }
  if (stuck_places_.size() >= kMaxStuckPlaces) stuck_places_.erase(stuck_places_.begin());
  stuck_places_.push_back(active_from_);
}

void Recovery::finish(const robot_observation_t& obs) {
  active_ = RecoveryBehavior::None;
  window_start_ = obs.utime;
  if (stuck_places_.size() >= kMaxStuckPlaces) stuck_places_.erase(stuck_places_.begin());
  stuck_places_.push_back(Vec2(obs.x, obs.y));
}

double Recovery::goalWeightFactor(const robot_observation_t& obs) const {
  if (!stuck() || !params_.enabled) return 1.0;
  const std::int64_t now = paused_at_ ? *paused_at_ : obs.utime;
  return 1.0 + params_.impatience * std::max(0.0, static_cast<double>(now - stuck_start_) * 1e-6);
}

double Recovery::elapsed(const robot_observation_t& obs) const {
  return static_cast<double>(obs.utime - active_start_) * 1e-6;
}

bool Recovery::command(const robot_observation_t& obs, const VelocityWindow& window, double heading_error,
                       const SafetyCheck& safe, double& v, double& w) {
  bool running = false;
  switch (active_) {
    case RecoveryBehavior::Spin:
      running = spin(obs, window, heading_error, safe, v, w);
      break;
    case RecoveryBehavior::BackUp:
      running = backUp(obs, window, safe, v, w);
      break;
    case RecoveryBehavior::Wait:
      // Brake as hard as the window allows and stand.
      running = elapsed(obs) < params_.wait_duration;
      v = window.clampV(0.0);
      w = window.clampW(0.0);
      break;
    case RecoveryBehavior::GiveWay:
      // On its way the planner plans toward the place (giveWayTarget()); there, it stands.
      if (give_way_target_ && !give_way_at_) return false;
      running = give_way_at_ && static_cast<double>(obs.utime - *give_way_at_) * 1e-6 < params_.wait_duration;
      v = window.clampV(0.0);
      w = window.clampW(0.0);
      break;
    case RecoveryBehavior::None:
    case RecoveryBehavior::ClearAndReplan:
    case RecoveryBehavior::Reroute:
      return false;
  }
  if (!running) finish(obs);
  return running;
}

bool Recovery::spin(const robot_observation_t& obs, const VelocityWindow& window, double heading_error,
                    const SafetyCheck& safe, double& v, double& w) {
  // Toward the path: the robot failed facing where it was; turning further that way opens arcs
  // that swing around what blocked it.
  if (spin_side_ == 0) spin_side_ = heading_error < 0.0 ? -1 : 1;
  turned_ += spin_side_ * normalizeAngle(obs.yaw - last_yaw_);
  last_yaw_ = obs.yaw;
  const double remaining = params_.spin_angle - turned_;
  if (remaining <= kSpinTolerance || elapsed(obs) >= params_.time_allowance) return false;
  // As fast as allowed, slowing down so as to stop at the angle (nav2's spin does the same).
  const double speed = std::min({params_.spin_speed, obs.max_w, std::sqrt(2.0 * obs.max_acc_w * remaining)});
  v = window.clampV(0.0);
  w = window.clampW(spin_side_ * speed);
  return safe(v, w, std::max(kMinMotionTime, remaining / speed));
}

bool Recovery::backUp(const robot_observation_t& obs, const VelocityWindow& window, const SafetyCheck& safe, double& v,
                      double& w) {
  const double remaining = params_.backup_distance - (Vec2(obs.x, obs.y) - active_from_).norm();
  if (remaining <= 0.0 || elapsed(obs) >= params_.time_allowance) return false;
  const double speed = std::min(params_.backup_speed, -obs.min_v);
  v = window.clampV(-speed);
  w = window.clampW(0.0);
  // The whole rest of the way must be free, not only the next cycle's.
  return safe(-speed, 0.0, std::max(kMinMotionTime, remaining / speed));
}

}  // namespace hunav::planners
