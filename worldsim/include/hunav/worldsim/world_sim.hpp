#pragma once
// The world process logic: owns the clock, runs episodes over the step protocol (lcmtypes/README.md, "One tick in
// lockstep") and publishes what is true at every tick.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <hunav/episode_event_t.hpp>
#include <hunav/map_t.hpp>
#include <hunav/planner_ready_t.hpp>
#include <hunav/robot_command_t.hpp>
#include <hunav/robot_observation_t.hpp>
#include <hunav/step_reply_t.hpp>
#include <hunav/step_request_t.hpp>
#include <hunav/world_state_t.hpp>
#include <memory>
#include <optional>
#include <random>
#include <string>

#include "hunav/bus.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/fingerprint.hpp"
#include "hunav/scenario.hpp"

namespace hunav::worldsim {

class PhysicsWorld;   // the Box2D world (src/physics_world.hpp)
class StuckDetector;  // src/stuck_detector.hpp

struct WorldOptions {
  std::string planner = "dwb";                     // reported in events; "none" runs without a planner (robot stands)
  std::string mode = "lockstep";                   // inprocess | lockstep | realtime (realtime: wall-clock paced,
                                                   // the robot uses the latest command instead of waiting for it)
  std::string run_id;                              // default: <scenario>_<planner>_s<seed>
  std::chrono::milliseconds resend_after{100};     // resend a request unanswered this long
  std::chrono::milliseconds silence_limit{1000};   // abort after this long without an answer
  std::chrono::milliseconds startup_limit{10000};  // same, for a component's first answer of an episode
  const std::atomic<bool>* stop = nullptr;         // set (e.g. by SIGINT) to end the episode early
  // Why `stop` was set (empty: the process's, episode_status::stopCause()): a runner of several
  // episodes at once stops one of them with a reason of its own (hunav_run --runs' wall-clock limit).
  std::function<episode_status::StopCause()> stop_cause;
  // The caller of tick() drives the robot (command()), not a planner on the bus: a control tick stops
  // before the planner exchange with the observation pending (the Python module's step()).
  bool external_control = false;
  // > 0: before its first episode the world waits this long for the planner's PLANNER_READY
  // (docs/planner_contract.md, "Readiness"); without one the episode ends at once, aborted. 0: no wait
  // (a planner in this process, or none).
  std::chrono::milliseconds planner_ready_timeout{0};
  // The robot is not in the world (the robot-free run of a counterfactual, docs/metrics.md): no
  // Box2D body, never in a person's sight (robot_in_sight false), never stuck; needs planner "none".
  // The messages still carry a robot entry standing at its start pose: the manager must be told to
  // ignore it (AgentManager::setRobotAbsent).
  bool robot_absent = false;
};

struct EpisodeResult {
  std::string status;  // goal_reached | time_limit | stuck | aborted (episode_status.hpp)
  std::string reason;
  std::int64_t ticks = 0;        // world states published, tick 0 included
  double sim_time = 0.0;         // s
  double wall_time = 0.0;        // s
  double thread_cpu_time = 0.0;  // s of CPU time of the thread that ran the episode loop (START to END)
  std::string fingerprint;
  std::uint64_t collisions = 0;        // contact events of the episode (the sum over its world states)
  std::uint64_t dropped_messages = 0;  // the world dropped in the episode (its END event's count)
  // What the manager and the planner dropped in the episode, as their step replies and PLANNER_READY
  // announcements told; -1 when the world heard no count (no people, no planner, a silent one).
  std::int64_t manager_dropped_messages = -1;
  std::int64_t planner_dropped_messages = -1;
  std::string run_id;
  std::uint64_t seed = 0;
  // The episode ran to an end of its own (goal_reached, time_limit or stuck: an outcome of the
  // experiment), not aborted.
  bool ended() const { return episode_status::ranToEnd(status); }
};

class WorldSim {
 public:
  WorldSim(Bus& bus, Scenario scenario, WorldOptions options);
  ~WorldSim();

  // Runs one episode from the scenario's initial state; every call is a fresh world and a new
  // episode number.
  EpisodeResult runEpisode();
  // Runs the next episode on another scenario (typically the same file loaded with the next seed) under
  // its own run id (empty: <scenario>_<planner>_s<seed>). Nothing of earlier episodes carries over but
  // the episode counter.
  EpisodeResult runEpisode(Scenario scenario, std::string run_id);

  // runEpisode() in pieces, for a caller that advances the episode itself (the same ticks, so the
  // same results): beginEpisode(), then tick() until it returns true, then endEpisode().
  void beginEpisode();
  // One tick of the loop; true when the episode has ended (result's status and reason set). With
  // external_control a control tick returns false early with awaitingCommand() set: give command()
  // (else the last command holds) and call tick() again to finish that tick.
  bool tick(EpisodeResult& result);
  // Fills the rest of `result` and publishes the END event.
  void endEpisode(EpisodeResult& result);
  bool awaitingCommand() const { return awaiting_command_; }
  // The observation of the pending control tick (external_control).
  const robot_observation_t& pendingObservation() const { return pending_observation_; }
  // The command for the pending control tick; throws BadMessage on a non-finite value.
  void command(double v, double vy, double w);

  // Ground truth at the current tick (what the last world state held).
  const std::vector<agent_state_t>& agents() const { return agents_; }
  const agent_state_t& robot() const { return robot_state_; }
  std::int64_t tickCount() const { return tick_; }
  std::int64_t episode() const { return episode_; }
  double time() const { return simTime(); }
  std::uint64_t collisions() const { return collisions_; }
  // Of those, the contacts the robot is in (with a person or static geometry).
  std::uint64_t robotCollisions() const { return robot_collisions_; }
  // Of the world states published so far in this episode.
  std::string fingerprintSoFar() const { return fingerprint_.hex(); }

  const Scenario& scenario() const { return scenario_; }
  std::uint64_t resends() const { return resends_; }
  // Messages this world dropped so far: step replies and robot commands that did not decode or that
  // its checks rejected, and datagrams not in LCM's format on its sockets.
  std::uint64_t droppedMessages() const;

 private:
  void configure(Scenario scenario, std::string run_id);
  void reset();
  void sense();
  // The robot as an agent: every field (robotState), or only those that change as it moves.
  // The obstacle points of a body at p (people.obstacle_points), into out.
  void obstaclePoints(const Vec2& p, std::vector<Vec2>& out) const;
  agent_state_t robotState() const;
  void setRobotMotion(agent_state_t& r) const;
  void publishWorldState();
  // MAP: the static map as an occupancy grid, at START and when a planner asks (wants_map).
  void publishMap();
  void serveMapRequest();
  bool exchangeWithManager(std::string& failure);
  bool exchangeWithPlanner(std::string& failure);
  // Waits for PLANNER_READY (planner_ready_timeout). False with `failure` set when none came, false
  // with it empty when stopped.
  bool awaitPlannerReady(std::string& failure);
  // Ends the episode after a failed exchange: interrupted (or the supervisor's reason) when stopped.
  void abortWith(EpisodeResult& result, const std::string& failure) const;
  bool awaitReply(const std::function<void()>& send, const bool& arrived, bool first, const char* who, std::int64_t seq,
                  std::string& failure);
  robot_observation_t observation();
  // Moves the people's bodies with the motion of the last step reply.
  void applyReply();
  void driveRobot();
  bool robotAtGoal() const;
  // The end conditions of the loop, in order; true (status and reason set) when one holds.
  bool endReached(EpisodeResult& result);
  // Moves everything one tick (after the exchanges) and publishes the new world state.
  void advanceTick();
  void onStepReply(const step_reply_t& reply);
  void checkNotAhead(std::int64_t episode, std::int64_t seq, std::int64_t world_seq, const char* what) const;
  void onCommand(const robot_command_t& cmd);
  // Divided, not multiplied by 1e-6: the nearest double to the decimal time (18.26, not 18.259999999999998).
  double simTime() const { return static_cast<double>(time_us_) / 1e6; }

  Bus& bus_;
  Scenario scenario_;
  WorldOptions options_;
  bool realtime_;  // options_.mode == "realtime", compared once rather than per tick
  std::int64_t dt_us_;
  int control_every_;  // ticks per planner cycle

  std::unique_ptr<PhysicsWorld> physics_;
  std::vector<agent_state_t> agents_;
  agent_state_t robot_state_;  // as sensed at the current tick
  // Reused every tick so that steady-state ticks do not allocate.
  step_request_t request_;
  world_state_t world_state_;
  std::vector<std::uint8_t> encoded_;                      // of the last world state
  double robot_v_ = 0.0, robot_vy_ = 0.0, robot_w_ = 0.0;  // velocities the base is driving at (robot frame)
  double cmd_v_ = 0.0, cmd_vy_ = 0.0, cmd_w_ = 0.0;        // last command
  std::vector<Vec2> robot_obstacles_;
  std::vector<Vec2> obstacle_scratch_;
  std::vector<Vec2> positions_;  // of the people, this tick
  std::vector<char> in_sight_;
  std::vector<double> laser_ranges_;  // laserScan's ray casts
  std::vector<int32_t> reply_ids_;    // checkAgentStates' sort, for a reply out of id order
  std::mt19937_64 laser_rng_;
  std::mt19937_64 perception_rng_;

  std::int64_t episode_ = 0;
  std::int64_t tick_ = 0;
  std::int64_t time_us_ = 0;
  std::int64_t step_seq_ = 0;
  std::int64_t obs_seq_ = 0;
  bool manager_answered_ = false;  // within this episode
  bool planner_answered_ = false;
  // From the last step reply, per person: the velocity and heading the bodies take in the step (the
  // rest of the reply goes to agents_ when it arrives: only what the manager owns, nothing copied twice).
  struct NextMotion {
    double vx, vy, yaw;
  };
  std::vector<NextMotion> next_motion_;
  bool reply_arrived_ = false;
  bool command_arrived_ = false;
  bool planner_ready_ = false;  // a PLANNER_READY was heard (once is enough: later episodes do not wait)
  // MAP: the message of the current scenario's static map (rebuilt only when the shapes change), and a
  // planner's request to send it again (PLANNER_READY with wants_map), served at most every kMapResendPeriod.
  map_t map_;
  std::vector<Shape> map_shapes_;
  MapGrid map_grid_;
  bool map_built_ = false;
  bool map_requested_ = false;
  std::chrono::steady_clock::time_point map_sent_;
  // Realtime: when the last command arrived (or the episode began), to end a run whose planner
  // stalled or died (silence_limit; startup_limit before its first command).
  std::chrono::steady_clock::time_point last_command_;
  bool awaiting_command_ = false;  // external_control: a control tick waits for command()
  robot_observation_t pending_observation_;
  // Of the episode in progress (beginEpisode()).
  std::chrono::steady_clock::time_point wall_start_;
  double cpu_start_ = 0.0;
  std::int64_t limit_us_ = 0;
  episode_event_t event_;  // START, then END
  std::uint64_t collisions_ = 0;
  std::uint64_t robot_collisions_ = 0;
  std::uint64_t resends_ = 0;
  std::uint64_t dropped_at_last_end_ = 0;
  // A peer's drop count as it last told it (cumulative since it started), and its value at the last
  // END: the episode's share is the difference.
  struct PeerDrops {
    bool heard = false;
    std::uint64_t told = 0;
    std::uint64_t at_last_end = 0;
    void tell(std::int64_t count);
    std::int64_t takeEpisodeShare();  // -1 when never heard
  };
  PeerDrops manager_drops_;
  PeerDrops planner_drops_;
  std::unique_ptr<StuckDetector> stuck_;  // of the current episode (reset())
  Fingerprint fingerprint_;
  // Last, so that they end first: the handlers use the members above. Their drop counts are this
  // component's own (a bus in process is shared).
  Subscription reply_sub_;
  Subscription command_sub_;
  Subscription ready_sub_;
};

}  // namespace hunav::worldsim
