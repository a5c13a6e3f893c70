#include "hunav/runner/stepped_run.hpp"

#include <box2d/box2d.h>

#include <mutex>
#include <stdexcept>

#include "hunav/channels.hpp"
#include "hunav/in_process_bus.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/yaml_reader.hpp"
#include "run_assembly.hpp"
#include "run_components.hpp"

namespace hunav::runner {

namespace {
// Box2D 2.4 fills its table of contact types (b2Contact::s_registers, a global) when the first
// contact of the process is created, unguarded: two worlds stepped on two threads could both be
// first. One contact made here, once, before any SteppedRun ticks, fills it.
void initBox2dContactTypes() {
  static std::once_flag once;
  std::call_once(once, [] {
    b2World world(b2Vec2(0.0f, 0.0f));
    b2CircleShape circle;
    circle.m_radius = 1.0f;
    b2BodyDef def;
    def.type = b2_dynamicBody;
    world.CreateBody(&def)->CreateFixture(&circle, 1.0f);
    world.CreateBody(&def)->CreateFixture(&circle, 1.0f);
    world.Step(0.01f, 1, 1);  // the overlapping bodies' pair becomes a contact
  });
}
}  // namespace

SteppedRun::SteppedRun(const Scenario& scenario, const RunOptions& options, bool external)
    : options_(options), external_(external) {
  initBox2dContactTypes();
  if (options_.planner != "none" && !external_ && !planners::hasPlanner(options_.planner))
    throw std::invalid_argument("unknown planner '" + options_.planner + "'");
  manager::checkBehaviorTrees(scenario);  // a bad behavior_tree file: ConfigError before anything starts
  const std::unique_ptr<YamlReader> planner_config = plannerConfig(options_);

  bus_ = std::make_unique<InProcessBus>();
  RunParts parts;
  parts.evaluator = evaluatorOptions(scenario, options_);
  parts.evaluator->live_metrics = true;  // metrics() while the episode runs
  if (options_.planner != "none" && !external_)
    parts.planner = planners::createPlanner(options_.planner, scenario, planner_config.get());
  parts.world = worldOptions(options_);
  parts.world.external_control = external_;
  parts.threads = options_.threads;
  run_ = std::make_unique<AssembledRun>(*bus_, scenario, std::move(parts));
  world_ = &run_->world();
  // After the planner's own subscription: it answers first. (The world subscribes to neither channel.)
  live_sub_ = bus_->subscribe<live_metrics_t>(channels::kLiveMetrics, [this](const live_metrics_t& m) { live_ = m; });
  if (run_->planner() != nullptr)
    observation_sub_ = bus_->subscribe<robot_observation_t>(
        channels::kRobotObservation, [this](const robot_observation_t& o) { planner_observation_ = o; });
}

SteppedRun::~SteppedRun() = default;

void SteppedRun::start() {
  world_->beginEpisode();
  if (external_) {
    runToControl();
    return;
  }
  // A built-in planner: up to its first observation (the first tick), which reset() returns.
  while (run_->planner() != nullptr && planner_observation_.seq == 0 && !world_->tick(episode_)) {
  }
  if (!episode_.status.empty()) collect();
}

const robot_observation_t& SteppedRun::observation() const {
  return external_ ? world_->pendingObservation() : planner_observation_;
}

void SteppedRun::step(double v, double vy, double w) {
  if (!external_) throw std::logic_error("planner '" + options_.planner + "' drives the robot: use run()");
  if (ended()) throw std::logic_error("the episode has ended (" + episode_.status + "): call reset()");
  world_->command(v, vy, w);
  world_->tick(episode_);  // the rest of the pending control tick
  runToControl();
}

const RunOutcome& SteppedRun::finish() {
  while (!ended()) {
    world_->tick(episode_);
    runToControl();
  }
  return *outcome_;
}

const RunOutcome& SteppedRun::end(const std::string& status, const std::string& reason) {
  if (ended()) throw std::logic_error("the episode has ended (" + episode_.status + "): call reset()");
  episode_.status = status;
  episode_.reason = reason;
  collect();
  return *outcome_;
}

void SteppedRun::runToControl() {
  while (!world_->tick(episode_)) {
    if (world_->awaitingCommand()) return;
  }
  collect();
}

void SteppedRun::collect() {
  // As runInProcess() ends a run.
  world_->endEpisode(episode_);
  bus_->handleAvailable();
  if (!run_->evaluator()->finished())
    run_->evaluator()->finishIncomplete("the runner stopped before the episode END was recorded");
  RunOutcome outcome;
  outcome.episode = episode_;
  outcome.result = run_->evaluator()->lastResult();
  outcome.dropped_messages = bus_->droppedMessages();
  outcome_ = std::move(outcome);
}

}  // namespace hunav::runner
