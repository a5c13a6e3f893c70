// The `hunav` Python module: the in-process simulation (runner/stepped_run.hpp) stepped from Python,
// observations and ground truth as numpy arrays. python/README.md documents the API.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "hunav/bounds.hpp"
#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/evaluator/metrics.hpp"
#include "hunav/evaluator/result_files.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/occupancy_grid.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/runner/stepped_run.hpp"
#include "hunav/thread_pool.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace {

using hunav::runner::SteppedRun;

// One call at a time per object. reset(), step() and run() release the GIL while they work, so that
// another Python thread could enter the same object meanwhile (a crash, a hang, a Box2D allocator
// assertion): a call that finds the object busy raises RuntimeError instead. Those three hold the
// flag; every other method (which runs under the GIL) only checks it.
class BusyFlag {
 public:
  class Hold {
   public:
    explicit Hold(std::atomic<bool>* flag) : flag_(flag) {}
    Hold(Hold&& other) noexcept : flag_(std::exchange(other.flag_, nullptr)) {}
    Hold& operator=(Hold&&) = delete;
    ~Hold() {
      if (flag_ != nullptr) flag_->store(false);
    }

   private:
    std::atomic<bool>* flag_;
  };
  explicit BusyFlag(const char* owner) : owner_(owner) {}
  Hold hold() {
    bool idle = false;
    if (!busy_.compare_exchange_strong(idle, true)) throw busy();
    return Hold(&busy_);
  }
  void check() const {
    if (busy_.load()) throw busy();
  }

 private:
  std::runtime_error busy() const {
    return std::runtime_error(std::string(owner_) +
                              " is busy in another thread (its reset, step or run): use one object from one thread "
                              "at a time, or one object per thread");
  }
  const char* owner_;
  std::atomic<bool> busy_{false};
};

py::array_t<double> doubles(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

// An (n, cols) float64 array filled row by row by fill(i, row).
template <class Fill>
py::array_t<double> table(std::size_t n, std::size_t cols, Fill fill) {
  py::array_t<double> a({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(cols)});
  double* p = a.mutable_data();
  for (std::size_t i = 0; i < n; ++i) fill(i, p + i * cols);
  return a;
}

template <class T, class Get>
py::array_t<T> column(std::size_t n, Get get) {
  py::array_t<T> a(static_cast<py::ssize_t>(n));
  T* p = a.mutable_data();
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<T>(get(i));
  return a;
}

py::dict observationDict(const hunav::robot_observation_t& o) {
  py::dict d;
  d["robot"] = doubles({o.x, o.y, o.yaw, o.v, o.w});
  d["goal"] = doubles({o.goal.x, o.goal.y, o.goal.yaw, o.goal.radius});
  d["goal_valid"] = static_cast<bool>(o.goal.valid);
  py::array_t<float> scan(static_cast<py::ssize_t>(o.scan.ranges.size()));
  std::copy(o.scan.ranges.begin(), o.scan.ranges.end(), scan.mutable_data());
  d["scan"] = scan;
  d["scan_angle_min"] = o.scan.angle_min;  // beam i at angle_min + i * angle_increment from the heading
  d["scan_angle_increment"] = o.scan.angle_increment;
  const auto& people = o.people;
  d["people"] = table(people.size(), 6, [&](std::size_t i, double* r) {
    const auto& p = people[i];
    const double row[6] = {p.x, p.y, p.yaw, p.vx, p.vy, p.radius};
    std::copy(row, row + 6, r);
  });
  d["people_ids"] = column<std::int32_t>(people.size(), [&](std::size_t i) { return people[i].id; });
  d["time"] = static_cast<double>(o.utime) / 1e6;
  d["seq"] = o.seq;
  return d;
}

py::dict agentsDict(const std::vector<hunav::agent_state_t>& a) {
  const std::size_t n = a.size();
  py::dict d;
  d["id"] = column<std::int32_t>(n, [&](std::size_t i) { return a[i].id; });
  d["pose"] = table(n, 3, [&](std::size_t i, double* r) { r[0] = a[i].x, r[1] = a[i].y, r[2] = a[i].yaw; });
  d["velocity"] = table(n, 3, [&](std::size_t i, double* r) { r[0] = a[i].vx, r[1] = a[i].vy, r[2] = a[i].vyaw; });
  d["radius"] = column<double>(n, [&](std::size_t i) { return a[i].radius; });
  d["behavior"] = column<std::int8_t>(n, [&](std::size_t i) { return a[i].behavior; });
  d["behavior_state"] = column<std::int8_t>(n, [&](std::size_t i) { return a[i].behavior_state; });
  d["group"] = column<std::int32_t>(n, [&](std::size_t i) { return a[i].group_id; });
  d["robot_in_sight"] = column<bool>(n, [&](std::size_t i) { return a[i].robot_in_sight; });
  // The current goal (the head of the queue); NaN for none.
  d["goal"] = table(n, 2, [&](std::size_t i, double* r) {
    const bool has = !a[i].goals.empty();
    r[0] = has ? a[i].goals[0].x : std::nan("");
    r[1] = has ? a[i].goals[0].y : std::nan("");
  });
  py::list names;
  for (const auto& s : a) names.append(s.name);
  d["name"] = names;
  return d;
}

py::dict metricsDict(const std::vector<std::string>& names, const std::vector<double>& values) {
  py::dict d;
  for (std::size_t i = 0; i < names.size() && i < values.size(); ++i) d[py::str(names[i])] = values[i];
  return d;
}

// A fresh folder for one episode's result files when the user gave none.
fs::path makeTempDir() {
  std::string templ = (fs::temp_directory_path() / "hunav-py-XXXXXX").string();
  if (mkdtemp(templ.data()) == nullptr) throw std::runtime_error("cannot create a temporary folder");
  return templ;
}

// hunav.gym's observation of one world (python/hunav/gym.py): robot [v, w]; goal relative to the
// robot in its frame (x ahead, y left); the scan clipped to [0, range_max]; the perceived people
// nearest first as [dx, dy, vx, vy, radius, 1] in the robot frame, then rows of 0. Done here: numpy's
// cost per call dwarfs the arithmetic on arrays of a few elements (docs/performance.md, "Python").
// `order` is the caller's
// scratch (kept between steps, so that sorting the people allocates nothing).
using NearestFirst = std::vector<std::pair<double, std::size_t>>;
void robotFrame(const hunav::robot_observation_t& o, std::size_t max_people, float range_max, float* robot, float* goal,
                float* scan, std::size_t beams, float* people, NearestFirst& order) {
  const double c = std::cos(o.yaw), s = std::sin(o.yaw);
  robot[0] = static_cast<float>(o.v);
  robot[1] = static_cast<float>(o.w);
  const double gx = o.goal.x - o.x, gy = o.goal.y - o.y;
  goal[0] = static_cast<float>(c * gx + s * gy);
  goal[1] = static_cast<float>(-s * gx + c * gy);
  const auto& r = o.scan.ranges;
  for (std::size_t i = 0; i < beams; ++i) scan[i] = i < r.size() ? std::min(std::max(r[i], 0.0f), range_max) : 0.0f;
  const std::size_t k = o.people.size();
  order.clear();
  for (std::size_t i = 0; i < k; ++i) {
    const double dx = o.people[i].x - o.x, dy = o.people[i].y - o.y;
    order.emplace_back(std::hypot(c * dx + s * dy, -s * dx + c * dy), i);
  }
  std::sort(order.begin(), order.end());  // by distance, then index
  std::fill(people, people + max_people * 6, 0.0f);
  for (std::size_t j = 0; j < std::min(k, max_people); ++j) {
    const auto& p = o.people[order[j].second];
    const double dx = p.x - o.x, dy = p.y - o.y;
    float* row = people + j * 6;
    row[0] = static_cast<float>(c * dx + s * dy);
    row[1] = static_cast<float>(-s * dx + c * dy);
    row[2] = static_cast<float>(c * p.vx + s * p.vy);
    row[3] = static_cast<float>(-s * p.vx + c * p.vy);
    row[4] = static_cast<float>(p.radius);
    row[5] = 1.0f;
  }
}

// hunav.gym's observation (robotFrame) as float32 arrays robot (2,), goal (2,), scan (beams,) and
// people (max_people, 6): of one world, or of `worlds` worlds stacked on a leading axis.
class RobotFrameArrays {
 public:
  RobotFrameArrays(std::optional<std::size_t> worlds, std::size_t beams, std::size_t max_people)
      : beams_(beams),
        max_people_(max_people),
        robot_(shape(worlds, {2})),
        goal_(shape(worlds, {2})),
        scan_(shape(worlds, {beams})),
        people_(shape(worlds, {max_people, 6})) {}

  // Writes world i's observation (i = 0 for one world).
  void fill(std::size_t i, const hunav::robot_observation_t& o, float range_max, NearestFirst& order) {
    robotFrame(o, max_people_, range_max, robot_.mutable_data() + 2 * i, goal_.mutable_data() + 2 * i,
               scan_.mutable_data() + beams_ * i, beams_, people_.mutable_data() + max_people_ * 6 * i, order);
  }

  py::dict dict() const {
    py::dict d;
    d["robot"] = robot_;
    d["goal"] = goal_;
    d["scan"] = scan_;
    d["people"] = people_;
    return d;
  }

 private:
  static std::vector<py::ssize_t> shape(std::optional<std::size_t> worlds, std::initializer_list<std::size_t> dims) {
    std::vector<py::ssize_t> s;
    if (worlds) s.push_back(static_cast<py::ssize_t>(*worlds));
    for (std::size_t d : dims) s.push_back(static_cast<py::ssize_t>(d));
    return s;
  }

  std::size_t beams_, max_people_;
  py::array_t<float> robot_, goal_, scan_, people_;
};

}  // namespace

// Python's hunav.Simulation: loads the scenario once per seed and builds a SteppedRun per episode.
class Simulation {
 public:
  Simulation(std::string scenario_file, std::optional<long long> seed, std::optional<std::string> planner,
             std::optional<double> duration, std::optional<double> sample_rate, std::string planner_config,
             std::string profile, std::string out_dir, std::optional<std::string> experiment_tag, std::string run_id,
             std::string metrics_file, std::string format, bool evaluator_thread = true, bool states_csv = true,
             bool per_tick_files = true, bool files = true, std::optional<std::string> people_model = std::nullopt)
      : file_(std::move(scenario_file)),
        people_model_(std::move(people_model)),
        duration_(duration.value_or(0.0)),
        sample_rate_(sample_rate),
        metrics_file_(std::move(metrics_file)),
        experiment_tag_(std::move(experiment_tag)),
        keep_out_dir_(!out_dir.empty()),
        files_(files) {
    if (seed && *seed < 0) throw std::invalid_argument("seed must be >= 0");
    if (!files && !out_dir.empty())
      throw std::invalid_argument("out_dir is for result files, and files=False writes none: give one of them");
    // 0 is no duration (it kept the scenario's time limit): None is how to keep it.
    if (duration && !(*duration > 0.0 && *duration <= hunav::kMaxTimeLimit))
      throw std::invalid_argument("duration must be a number of seconds in (0, 1e7] (None: the scenario's time limit)");
    if (sample_rate) hunav::evaluator::SampleRate{*sample_rate};  // the evaluator's own check
    if (format != "csv" && format != "hunav_txt")
      throw std::invalid_argument("format must be 'csv' or 'hunav_txt', not '" + format + "'");
    // Without a built-in planner the robot is driven from Python, recorded as planner "python".
    external_ = !planner.has_value();
    options_.planner = planner.value_or("python");
    if (!external_ && options_.planner != "none" && !hunav::planners::hasPlanner(options_.planner))
      throw std::invalid_argument("unknown planner '" + options_.planner + "'");
    options_.planner_config = std::move(planner_config);
    options_.profile = std::move(profile);
    options_.out_dir = std::move(out_dir);
    options_.hunav_txt = format == "hunav_txt";
    options_.run_id = std::move(run_id);
    options_.states_csv = states_csv;
    options_.per_tick_files = per_tick_files;
    // Its own threads: a lane for the evaluator's per-sample work and a helper for large crowds.
    // Without them everything runs on the stepping thread (the same results): what VectorSimulation
    // wants, whose own threads keep the cores busy.
    if (evaluator_thread) {
      threads_ = std::make_unique<hunav::ThreadPool>(hunav::ThreadPool::forThisMachine(1));
      options_.threads = threads_.get();
    }
    load(seed.value_or(-1));  // a bad scenario or metrics file raises here, before any reset()
  }
  ~Simulation() {
    run_.reset();
    removeTempDir();
  }

  py::dict reset(std::optional<long long> seed, std::optional<std::string> out_dir) {
    checkSeed(seed);
    checkOutDir(out_dir);
    {
      const BusyFlag::Hold hold = busy_.hold();
      py::gil_scoped_release release;
      resetNative(seed, out_dir);
    }
    return observation();
  }

  py::dict step(double v, double w, double vy) {
    checkCommand(v, w, vy);
    {
      const BusyFlag::Hold hold = busy_.hold();
      py::gil_scoped_release release;
      run_->step(v, vy, w);
    }
    return observation();
  }

  // Held by a VectorSimulation while its threads work on this world.
  BusyFlag& busy() { return busy_; }

  // The parts of reset() and step() without Python (VectorSimulation runs them on its threads).
  static void checkSeed(std::optional<long long> seed) {
    if (seed && *seed < 0) throw std::invalid_argument("seed must be >= 0");
  }
  static void checkOutDir(const std::optional<std::string>& out_dir) {
    if (out_dir && out_dir->empty()) throw std::invalid_argument("out_dir is empty (None: the simulation's own)");
  }
  // out_dir: this episode's result folder; else the constructor's out_dir, a temporary folder, or
  // (files=False) no files at all.
  void resetNative(std::optional<long long> seed, const std::optional<std::string>& out_dir = std::nullopt) {
    if (seed && static_cast<std::uint64_t>(*seed) != scenario_.seed) load(*seed);
    run_.reset();
    removeTempDir();
    hunav::runner::RunOptions o = options_;
    if (out_dir)
      o.out_dir = *out_dir;
    else if (!files_)
      o.write_files = false;
    else if (o.out_dir.empty())
      o.out_dir = (temp_dir_ = makeTempDir()).string();
    run_ = std::make_unique<SteppedRun>(scenario_, o, external_);
    run_->start();
  }
  // Throws what step() would for this command, before anything moves.
  void checkCommand(double v, double w, double vy) const {
    SteppedRun& r = started();
    if (!r.external()) throw std::logic_error("planner '" + options_.planner + "' drives the robot: use run()");
    if (r.ended()) throw std::logic_error("the episode has ended (" + r.episode().status + "): call reset()");
    for (const auto& [x, name] : {std::pair{v, "v"}, {w, "w"}, {vy, "vy"}})
      if (!std::isfinite(x)) throw std::invalid_argument(std::string(name) + " is not finite");
    if (vy != 0.0 && scenario_.robot.drive != hunav::RobotDrive::Holonomic)
      throw std::invalid_argument("vy is for a holonomic robot; this one has a differential drive");
  }
  void stepNative(double v, double w, double vy) { run_->step(v, vy, w); }
  void finishNative() {
    if (!run_) resetNative(std::nullopt);
    run_->finish();
  }
  const hunav::robot_observation_t& rawObservation() const { return started().observation(); }
  const hunav::worldsim::WorldSim& world() const { return started().world(); }
  bool hasEpisode() const {
    busy_.check();
    return run_ != nullptr;
  }

  py::dict run() {
    {
      const BusyFlag::Hold hold = busy_.hold();
      py::gil_scoped_release release;
      finishNative();
    }
    return info();
  }

  py::dict observation() const { return observationDict(started().observation()); }

  py::dict info() const {
    const SteppedRun& r = started();
    const auto& w = r.world();
    py::dict d;
    d["status"] = r.ended() ? r.episode().status : std::string("running");
    d["reason"] = r.episode().reason;
    d["done"] = r.ended();
    d["goal_reached"] = r.episode().status == "goal_reached";
    d["time_limit"] = r.episode().status == "time_limit";
    d["stuck"] = r.episode().status == "stuck";
    d["time"] = w.time();
    d["ticks"] = w.tickCount() + 1;
    d["collisions"] = w.collisions();
    d["robot_collisions"] = w.robotCollisions();
    d["seed"] = scenario_.seed;
    d["fingerprint"] = fingerprint();
    if (r.ended()) d["wall_time"] = r.episode().wall_time;
    return d;
  }

  py::dict state() const {
    const auto& w = started().world();
    const auto& rb = w.robot();
    py::dict d;
    d["time"] = w.time();
    d["tick"] = w.tickCount();
    d["robot"] = doubles({rb.x, rb.y, rb.yaw, rb.vx, rb.vy, rb.vyaw, rb.radius});
    d["agents"] = agentsDict(w.agents());
    d["collisions"] = w.collisions();
    d["robot_collisions"] = w.robotCollisions();
    return d;
  }

  // hunav.gym's observation (robotFrame) as a dict of float32 arrays.
  py::dict robotFrameObservation(std::size_t max_people, float range_max) const {
    RobotFrameArrays a(std::nullopt, beams(), max_people);
    fillRobotFrame(a, 0, range_max);
    return a.dict();
  }
  // Writes this world's robotFrame observation as world i of `a`.
  void fillRobotFrame(RobotFrameArrays& a, std::size_t i, float range_max) const {
    a.fill(i, started().observation(), range_max, people_order_);
  }
  std::size_t beams() const { return static_cast<std::size_t>(std::max(0, scenario().robot.laser.beams)); }

  // The terms of hunav.gym's default reward after the step: the robot's distance to its goal,
  // sum_i max(0, (personal_distance - d_i) / personal_distance) over every person i (d_i centre to
  // centre), and the robot's collision count.
  py::tuple rewardTerms(double personal_distance) const {
    const auto& w = started().world();
    const auto& rb = w.robot();
    double intrusion = 0.0;
    for (const auto& a : w.agents())
      intrusion += std::max(0.0, (personal_distance - std::hypot(a.x - rb.x, a.y - rb.y)) / personal_distance);
    const auto& g = scenario_.robot.goal;
    return py::make_tuple(std::hypot(rb.x - g.x(), rb.y - g.y()), intrusion, w.robotCollisions());
  }

  // The ground truth a reward needs, cheaply: robot [x, y, yaw], people positions (n, 2), and the
  // robot's collision count (hunav.gym's default reward, every step).
  py::tuple positions() const {
    const auto& w = started().world();
    const auto& rb = w.robot();
    const auto& a = w.agents();
    return py::make_tuple(doubles({rb.x, rb.y, rb.yaw}),
                          table(a.size(), 2,
                                [&](std::size_t i, double* r) {
                                  r[0] = a[i].x;
                                  r[1] = a[i].y;
                                }),
                          w.robotCollisions());
  }

  py::dict metrics() const {
    const SteppedRun& r = started();
    if (r.ended() && r.outcome()->result) {
      std::vector<std::string> names;
      std::vector<double> values;
      for (const auto& m : r.outcome()->result->metrics) names.push_back(m.name), values.push_back(m.value);
      return metricsDict(names, values);
    }
    return metricsDict(r.liveMetrics().names, r.liveMetrics().values);
  }

  std::string fingerprint() const {
    const SteppedRun& r = started();
    return r.ended() ? r.episode().fingerprint : r.world().fingerprintSoFar();
  }

  // Ends the running episode with `status` ("collision", or "aborted" for a rule of the caller's own)
  // and `reason`, as if it had ended so: END, the final metrics and the result files.
  py::dict endEpisode(const std::string& status, const std::string& reason) {
    namespace st = hunav::episode_status;
    if (status != st::kCollision && status != st::kAborted)
      throw std::invalid_argument("end_episode: status must be 'collision' or 'aborted', not '" + status + "'");
    if (reason.empty()) throw std::invalid_argument("end_episode: give a reason");
    SteppedRun& r = started();
    {
      const BusyFlag::Hold hold = busy_.hold();
      py::gil_scoped_release release;
      r.end(status, reason);
    }
    return info();
  }

  // Copies the episode's result files (metrics.csv, states.csv, run.json, ...) into out_dir. An
  // episode recorded without files gets those that need no samples (writeRunSummaries), and a
  // UserWarning naming what is missing and how to have it.
  std::string save(const std::string& out_dir) const {
    const SteppedRun& r = started();
    if (!r.ended() || !r.outcome()->result)
      throw std::logic_error("the episode is still running: step() or run() it to the end first");
    if (r.outcome()->result->metrics_csv.empty()) {
      hunav::evaluator::RunResult result = *r.outcome()->result;
      hunav::evaluator::writeRunSummaries(result, out_dir, out_dir, options_.hunav_txt);
      if (PyErr_WarnEx(PyExc_UserWarning,
                       "save() wrote metrics.csv, the per-behavior metrics files and run.json only: states.csv and the "
                       "per-tick metric files need the rows of every sample, which an episode recorded without files "
                       "does not keep (HuNavEnv / HuNavVectorEnv: give results_dir=; Simulation: files=True, or "
                       "reset(out_dir=...))",
                       1) != 0)
        throw py::error_already_set();
      return fs::path(out_dir).string();
    }
    const fs::path from = r.outcome()->result->metrics_csv.parent_path();
    fs::create_directories(out_dir);
    fs::copy(from, out_dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    return fs::path(out_dir).string();
  }

  py::dict mapDict() const { return mapOf(scenario()); }
  // The static map as the world publishes it on MAP (occupancy_grid.hpp): resolution (m), origin
  // [x, y] of cell (0, 0)'s outer corner, cells (height, width) int8 (0 free, 100 occupied), row j
  // column i at origin + (i + 0.5, j + 0.5) * resolution.
  py::dict occupancyGridDict() const {
    const hunav::OccupancyGrid g = hunav::occupancyGrid(scenario());
    py::array_t<std::int8_t> cells({static_cast<py::ssize_t>(g.height), static_cast<py::ssize_t>(g.width)});
    std::copy(g.cells.begin(), g.cells.end(), cells.mutable_data());
    py::dict d;
    d["resolution"] = g.resolution;
    d["origin"] = doubles({g.origin.x(), g.origin.y()});
    d["cells"] = cells;
    return d;
  }
  py::dict robotDict() const {
    const auto& rc = scenario().robot;
    const auto& l = rc.limits;
    py::dict d;
    d["radius"] = rc.radius;
    d["holonomic"] = rc.drive == hunav::RobotDrive::Holonomic;
    d["max_v"] = l.max_v, d["min_v"] = l.min_v, d["max_w"] = l.max_w, d["max_vy"] = l.max_vy;
    d["max_acc_v"] = l.max_acc_v, d["max_acc_w"] = l.max_acc_w;
    d["control_period"] = std::max(1L, std::lround(1.0 / (rc.control_rate * scenario().dt))) * scenario().dt;
    d["laser_beams"] = rc.laser.beams, d["laser_fov"] = rc.laser.fov;
    d["laser_range_min"] = rc.laser.range_min, d["laser_range_max"] = rc.laser.range_max;
    d["start"] = doubles({rc.start.x(), rc.start.y(), rc.start_yaw});
    d["goal"] = doubles({rc.goal.x(), rc.goal.y(), rc.goal_yaw, rc.goal_radius});
    d["has_goal"] = rc.has_goal;
    return d;
  }
  const hunav::Scenario& scenario() const {
    busy_.check();
    return scenario_;
  }
  bool done() const {
    busy_.check();
    return run_ && run_->ended();
  }
  std::string planner() const { return options_.planner; }
  bool external() const { return external_; }
  double sampleRate() const { return scenario().evaluation_sample_rate; }
  std::string experimentTag() const {
    busy_.check();  // reset(seed) reloads the metrics file
    return options_.experiment_tag;
  }
  std::string metricsFile() const {
    busy_.check();
    return options_.metrics_file;
  }

 private:
  // The map's walls as segments (x0, y0, x1, y1), circles (x, y, r) and the scenario's bounds.
  static py::dict mapOf(const hunav::Scenario& s) {
    std::vector<double> seg, circ;
    for (const hunav::Shape& sh : s.shapes) {
      if (sh.kind == hunav::Shape::Kind::Circle) {
        circ.insert(circ.end(), {sh.center.x(), sh.center.y(), sh.radius});
        continue;
      }
      const std::size_t n = sh.points.size();
      const std::size_t edges = sh.kind == hunav::Shape::Kind::Polygon ? n : (n > 0 ? n - 1 : 0);
      for (std::size_t i = 0; i < edges; ++i) {
        const auto& a = sh.points[i];
        const auto& b = sh.points[(i + 1) % n];
        seg.insert(seg.end(), {a.x(), a.y(), b.x(), b.y()});
      }
    }
    hunav::Vec2 lo, hi;
    s.bounds(lo, hi);
    py::dict d;
    d["segments"] = table(seg.size() / 4, 4, [&](std::size_t i, double* r) { std::copy_n(&seg[i * 4], 4, r); });
    d["circles"] = table(circ.size() / 3, 3, [&](std::size_t i, double* r) { std::copy_n(&circ[i * 3], 3, r); });
    d["bounds"] = doubles({lo.x(), lo.y(), hi.x(), hi.y()});
    return d;
  }

  // As hunav_run: the seed and duration replace the scenario's; the metrics file (else the
  // scenario's evaluation.metrics) selects the metrics, and its frequency and experiment_tag apply
  // unless sample_rate / experiment_tag were given.
  void load(long long seed) {
    scenario_ = hunav::cli::loadScenarioFor(file_, seed, duration_);
    if (sample_rate_) scenario_.evaluation_sample_rate = *sample_rate_;
    if (people_model_) hunav::overridePeopleModel(scenario_, *people_model_);
    options_.metrics_file = metrics_file_.empty() ? scenario_.evaluation_metrics : metrics_file_;
    options_.experiment_tag = experiment_tag_.value_or("exp");
    hunav::evaluator::applyMetricsFile(options_.metrics_file, options_.profile, sample_rate_.has_value(),
                                       scenario_.evaluation_sample_rate, experiment_tag_.has_value(),
                                       options_.experiment_tag);
  }
  SteppedRun& started() const {
    busy_.check();
    if (!run_) throw std::logic_error("no episode yet: call reset() first");
    return *run_;
  }
  void removeTempDir() {
    if (temp_dir_.empty() || keep_out_dir_) return;
    std::error_code ec;  // best effort: a leftover temporary folder is no error
    fs::remove_all(temp_dir_, ec);
    temp_dir_.clear();
  }

  std::string file_;
  std::optional<std::string> people_model_;  // every person's model (None: the scenario's)
  double duration_;
  std::optional<double> sample_rate_;
  std::string metrics_file_;
  std::optional<std::string> experiment_tag_;
  bool keep_out_dir_;
  bool files_;  // false: episodes reset without an out_dir write no file
  bool external_ = false;
  std::unique_ptr<hunav::ThreadPool> threads_;  // before run_: outlives its nodes
  hunav::runner::RunOptions options_;
  hunav::Scenario scenario_;
  fs::path temp_dir_;
  std::unique_ptr<SteppedRun> run_;
  mutable NearestFirst people_order_;  // robotFrame's scratch
  BusyFlag busy_{"this hunav.Simulation"};
};

// Python's hunav.VectorSimulation: n Simulations of one scenario, each with its own seed, reset and
// stepped together on a pool of threads it owns, with the GIL released. Each world's state is its
// own (no shared mutable state between worlds), so each episode is the one a single Simulation
// with the same seed and commands gives, whatever thread steps it.
class VectorSimulation {
 public:
  VectorSimulation(int n, const std::string& scenario, std::optional<std::vector<long long>> seeds,
                   std::optional<std::string> planner, std::optional<int> threads, std::optional<int> max_people,
                   std::optional<double> duration, std::optional<double> sample_rate, const std::string& planner_config,
                   const std::string& profile, std::optional<std::string> experiment_tag,
                   const std::string& metrics_file, const std::string& format, bool evaluator_thread, bool states_csv,
                   bool per_tick_files, bool files) {
    if (n < 1) throw std::invalid_argument("n must be >= 1");
    if (seeds && seeds->size() != static_cast<std::size_t>(n))
      throw std::invalid_argument("seeds has " + std::to_string(seeds->size()) + " values for " + std::to_string(n) +
                                  " worlds");
    if (threads && *threads < 1) throw std::invalid_argument("threads must be >= 1");
    if (max_people && *max_people < 0) throw std::invalid_argument("max_people must be >= 0");
    auto make = [&](std::optional<long long> seed) {
      return std::make_shared<Simulation>(scenario, seed, planner, duration, sample_rate, planner_config, profile, "",
                                          experiment_tag, "", metrics_file, format, evaluator_thread, states_csv,
                                          per_tick_files, files);
    };
    // Default seeds: the scenario's seed, then one more per world.
    sims_.push_back(make(seeds ? std::optional<long long>((*seeds)[0]) : std::nullopt));
    const auto base = static_cast<long long>(sims_[0]->scenario().seed);
    for (int i = 1; i < n; ++i) sims_.push_back(make(seeds ? (*seeds)[static_cast<std::size_t>(i)] : base + i));
    std::size_t people = 0;
    for (const auto& s : sims_) people = std::max(people, s->scenario().agents.size());
    max_people_ = max_people ? static_cast<std::size_t>(*max_people) : people;
    const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    // The caller's thread and threads - 1 helpers. They look for the next step for a while before
    // they sleep: a wake-up through the kernel costs about what a Python step takes between calls.
    hunav::ThreadPool::Size size;
    size.helpers = std::min(n, threads.value_or(cores)) - 1;
    size.spin = std::chrono::microseconds(200);
    pool_ = std::make_unique<hunav::ThreadPool>(size);
  }

  std::size_t size() const { return sims_.size(); }
  int threads() const { return pool_->slots(); }
  std::size_t maxPeople() const { return max_people_; }
  std::shared_ptr<Simulation> world(long long i) const { return sims_.at(index(i)); }

  py::dict reset(std::optional<std::vector<long long>> seeds, std::optional<std::vector<long long>> indices,
                 std::optional<std::vector<std::optional<std::string>>> out_dirs) {
    busy_.check();
    std::vector<std::size_t> worlds;
    if (indices) {
      std::vector<bool> seen(sims_.size());
      for (long long i : *indices) {
        const std::size_t k = index(i);
        if (seen[k]) throw std::invalid_argument("world " + std::to_string(k) + " is listed twice in indices");
        seen[k] = true;
        worlds.push_back(k);
      }
    } else {
      for (std::size_t k = 0; k < sims_.size(); ++k) worlds.push_back(k);
    }
    if (seeds && seeds->size() != worlds.size())
      throw std::invalid_argument("seeds has " + std::to_string(seeds->size()) + " values for " +
                                  std::to_string(worlds.size()) + " worlds");
    if (seeds)
      for (long long s : *seeds) Simulation::checkSeed(s);
    if (out_dirs && out_dirs->size() != worlds.size())
      throw std::invalid_argument("out_dirs has " + std::to_string(out_dirs->size()) + " values for " +
                                  std::to_string(worlds.size()) + " worlds");
    if (out_dirs)
      for (const auto& d : *out_dirs) Simulation::checkOutDir(d);
    parallel(worlds.size(), [&](std::size_t k) {
      sims_[worlds[k]]->resetNative(seeds ? std::optional<long long>((*seeds)[k]) : std::nullopt,
                                    out_dirs ? (*out_dirs)[k] : std::nullopt);
    });
    return observation();
  }

  // actions: (n, 2) [v, w] or (n, 3) [v, w, vy]; the rows of worlds whose episode has ended are
  // ignored (those worlds do not move).
  py::dict step(const py::array_t<double, py::array::c_style | py::array::forcecast>& actions) {
    requireEpisodes();
    const std::size_t n = sims_.size();
    if (actions.ndim() != 2 || actions.shape(0) != static_cast<py::ssize_t>(n) ||
        (actions.shape(1) != 2 && actions.shape(1) != 3)) {
      std::string shape;
      for (py::ssize_t d = 0; d < actions.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(actions.shape(d));
      if (actions.ndim() == 1) shape += ",";  // as Python writes a 1-tuple
      throw std::invalid_argument("actions of shape (" + shape + "), expected (" + std::to_string(n) +
                                  ", 2) [v, w] or (" + std::to_string(n) + ", 3) [v, w, vy]");
    }
    const std::size_t cols = static_cast<std::size_t>(actions.shape(1));
    const double* a = actions.data();
    std::vector<std::size_t> running;
    for (std::size_t i = 0; i < n; ++i) {
      if (sims_[i]->done()) continue;
      const double* row = a + i * cols;
      try {
        sims_[i]->checkCommand(row[0], row[1], cols == 3 ? row[2] : 0.0);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("world " + std::to_string(i) + ": " + e.what());
      } catch (const std::logic_error& e) {
        throw std::logic_error("world " + std::to_string(i) + ": " + e.what());
      }
      running.push_back(i);
    }
    if (running.empty()) throw std::logic_error("every world's episode has ended: call reset()");
    parallel(running.size(), [&](std::size_t k) {
      const double* row = a + running[k] * cols;
      sims_[running[k]]->stepNative(row[0], row[1], cols == 3 ? row[2] : 0.0);
    });
    return observation();
  }

  // Plays every world's episode to its end (starting those not started) and returns their info().
  py::list run() {
    busy_.check();
    parallel(sims_.size(), [&](std::size_t k) { sims_[k]->finishNative(); });
    return infos();
  }

  // The worlds' observations stacked: robot (n, 5), goal (n, 4), goal_valid (n,), scan (n, beams)
  // float32, people (n, max_people, 6) and people_ids (n, max_people) padded with 0 and -1,
  // people_count (n,), time (n,), seq (n,).
  py::dict observation() const {
    requireEpisodes();
    const std::size_t n = sims_.size(), m = max_people_;
    std::vector<const hunav::robot_observation_t*> obs(n);
    std::size_t beams = 0;
    for (std::size_t i = 0; i < n; ++i) {
      obs[i] = &sims_[i]->rawObservation();
      beams = std::max(beams, obs[i]->scan.ranges.size());
    }
    py::dict d;
    d["robot"] = table(n, 5, [&](std::size_t i, double* r) {
      const auto& o = *obs[i];
      r[0] = o.x, r[1] = o.y, r[2] = o.yaw, r[3] = o.v, r[4] = o.w;
    });
    d["goal"] = table(n, 4, [&](std::size_t i, double* r) {
      const auto& g = obs[i]->goal;
      r[0] = g.x, r[1] = g.y, r[2] = g.yaw, r[3] = g.radius;
    });
    d["goal_valid"] = column<bool>(n, [&](std::size_t i) { return obs[i]->goal.valid; });
    py::array_t<float> scan({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(beams)});
    float* sp = scan.mutable_data();
    for (std::size_t i = 0; i < n; ++i) {
      const auto& r = obs[i]->scan.ranges;
      std::fill(std::copy(r.begin(), r.end(), sp + i * beams), sp + (i + 1) * beams, 0.0f);
    }
    d["scan"] = scan;
    py::array_t<double> people({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(m), py::ssize_t{6}});
    py::array_t<std::int32_t> ids({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(m)});
    double* pp = people.mutable_data();
    std::int32_t* ip = ids.mutable_data();
    std::fill(pp, pp + n * m * 6, 0.0);
    std::fill(ip, ip + n * m, -1);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& ps = obs[i]->people;
      for (std::size_t k = 0; k < std::min(m, ps.size()); ++k) {
        const auto& p = ps[k];
        const double row[6] = {p.x, p.y, p.yaw, p.vx, p.vy, p.radius};
        std::copy(row, row + 6, pp + (i * m + k) * 6);
        ip[i * m + k] = p.id;
      }
    }
    d["people"] = people;
    d["people_ids"] = ids;
    d["people_count"] = column<std::int32_t>(n, [&](std::size_t i) { return std::min(m, obs[i]->people.size()); });
    d["time"] = column<double>(n, [&](std::size_t i) { return static_cast<double>(obs[i]->utime) / 1e6; });
    d["seq"] = column<std::int64_t>(n, [&](std::size_t i) { return obs[i]->seq; });
    return d;
  }

  // hunav.gym's observation (robotFrame) of every world, stacked.
  py::dict robotFrameObservation(std::size_t max_people, float range_max) const {
    requireEpisodes();
    RobotFrameArrays a(sims_.size(), sims_[0]->beams(), max_people);
    for (std::size_t i = 0; i < sims_.size(); ++i) sims_[i]->fillRobotFrame(a, i, range_max);
    return a.dict();
  }

  // Simulation.reward_terms of every world: (distance to goal (n,), intrusion (n,), robot collisions (n,)).
  py::tuple rewardTerms(double personal_distance) const {
    requireEpisodes();
    const std::size_t n = sims_.size();
    py::array_t<double> distance(static_cast<py::ssize_t>(n)), intrusion(static_cast<py::ssize_t>(n));
    py::array_t<std::uint64_t> collisions(static_cast<py::ssize_t>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const py::tuple t = sims_[i]->rewardTerms(personal_distance);
      distance.mutable_data()[i] = t[0].cast<double>();
      intrusion.mutable_data()[i] = t[1].cast<double>();
      collisions.mutable_data()[i] = t[2].cast<std::uint64_t>();
    }
    return py::make_tuple(distance, intrusion, collisions);
  }

  // Ground truth stacked: time, tick, robot (n, 7), collisions, robot_collisions, and agents with
  // count (n,) and id, pose, velocity, radius, behavior, behavior_state, group, robot_in_sight, goal
  // as (n, max_agents, ...) arrays (padding: id -1, 0 elsewhere, NaN goals).
  py::dict state() const {
    requireEpisodes();
    const std::size_t n = sims_.size();
    std::size_t m = 0;
    for (const auto& s : sims_) m = std::max(m, s->world().agents().size());
    auto agent = [&](std::size_t i, std::size_t k) -> const hunav::agent_state_t* {
      const auto& a = sims_[i]->world().agents();
      return k < a.size() ? &a[k] : nullptr;
    };
    const std::size_t nm = n * m;
    py::dict d;
    d["time"] = column<double>(n, [&](std::size_t i) { return sims_[i]->world().time(); });
    d["tick"] = column<std::int64_t>(n, [&](std::size_t i) { return sims_[i]->world().tickCount(); });
    d["robot"] = table(n, 7, [&](std::size_t i, double* r) {
      const auto& b = sims_[i]->world().robot();
      const double row[7] = {b.x, b.y, b.yaw, b.vx, b.vy, b.vyaw, b.radius};
      std::copy(row, row + 7, r);
    });
    d["collisions"] = column<std::uint64_t>(n, [&](std::size_t i) { return sims_[i]->world().collisions(); });
    d["robot_collisions"] =
        column<std::uint64_t>(n, [&](std::size_t i) { return sims_[i]->world().robotCollisions(); });
    auto per = [&](auto zero, auto get) {
      using T = decltype(zero);
      py::array_t<T> a({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(m)});
      T* p = a.mutable_data();
      for (std::size_t j = 0; j < nm; ++j) {
        const auto* s = agent(j / m, j % m);
        p[j] = s ? static_cast<T>(get(*s)) : zero;
      }
      return a;
    };
    auto triple = [&](std::size_t cols, auto get) {
      py::array_t<double> a({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(m), static_cast<py::ssize_t>(cols)});
      double* p = a.mutable_data();
      for (std::size_t j = 0; j < nm; ++j) {
        const auto* s = agent(j / m, j % m);
        get(s, p + j * cols);
      }
      return a;
    };
    const double nan = std::nan("");
    py::dict agents;
    agents["count"] = column<std::int32_t>(n, [&](std::size_t i) { return sims_[i]->world().agents().size(); });
    agents["id"] = per(std::int32_t{-1}, [](const hunav::agent_state_t& s) { return s.id; });
    agents["pose"] = triple(3, [](const hunav::agent_state_t* s, double* r) {
      r[0] = s ? s->x : 0.0, r[1] = s ? s->y : 0.0, r[2] = s ? s->yaw : 0.0;
    });
    agents["velocity"] = triple(3, [](const hunav::agent_state_t* s, double* r) {
      r[0] = s ? s->vx : 0.0, r[1] = s ? s->vy : 0.0, r[2] = s ? s->vyaw : 0.0;
    });
    agents["radius"] = per(0.0, [](const hunav::agent_state_t& s) { return s.radius; });
    agents["behavior"] = per(std::int8_t{0}, [](const hunav::agent_state_t& s) { return s.behavior; });
    agents["behavior_state"] = per(std::int8_t{0}, [](const hunav::agent_state_t& s) { return s.behavior_state; });
    agents["group"] = per(std::int32_t{-1}, [](const hunav::agent_state_t& s) { return s.group_id; });
    agents["robot_in_sight"] = per(false, [](const hunav::agent_state_t& s) { return s.robot_in_sight; });
    agents["goal"] = triple(2, [&](const hunav::agent_state_t* s, double* r) {
      const bool has = s && !s->goals.empty();
      r[0] = has ? s->goals[0].x : nan;
      r[1] = has ? s->goals[0].y : nan;
    });
    d["agents"] = agents;
    return d;
  }

  py::array_t<double> times() const {
    busy_.check();
    return column<double>(sims_.size(), [&](std::size_t i) { return sims_[i]->world().time(); });
  }
  py::array_t<bool> done() const {
    busy_.check();
    return column<bool>(sims_.size(), [&](std::size_t i) { return sims_[i]->done(); });
  }
  py::list infos() const {
    return each([](const Simulation& s) { return py::object(s.info()); });
  }
  py::list metrics() const {
    return each([](const Simulation& s) { return py::object(s.metrics()); });
  }
  py::list fingerprints() const {
    return each([](const Simulation& s) { return py::object(py::str(s.fingerprint())); });
  }
  py::list status() const {
    return each([](const Simulation& s) { return py::object(py::str(s.info()["status"])); });
  }
  std::vector<long long> seeds() const {
    std::vector<long long> out;
    for (const auto& s : sims_) out.push_back(static_cast<long long>(s->scenario().seed));
    return out;
  }

 private:
  std::size_t index(long long i) const {
    const auto n = static_cast<long long>(sims_.size());
    if (i < -n || i >= n)
      throw py::index_error("world " + std::to_string(i) + " out of range for " + std::to_string(n));
    return static_cast<std::size_t>(i < 0 ? i + n : i);
  }
  void requireEpisodes() const {
    busy_.check();
    for (std::size_t i = 0; i < sims_.size(); ++i)
      if (!sims_[i]->hasEpisode())
        throw std::logic_error("world " + std::to_string(i) + " has no episode yet: call reset() first");
  }
  template <class F>
  py::list each(F f) const {
    busy_.check();
    py::list out;
    for (const auto& s : sims_) out.append(f(*s));
    return out;
  }
  // f(k) for k in [0, count) on the pool, the GIL released, this object's flag and each world's held
  // (another call of this vector, or a world used alone, meanwhile raises); then rethrows the first
  // error (in k order).
  template <class F>
  void parallel(std::size_t count, F&& f) {
    const BusyFlag::Hold hold = busy_.hold();
    std::vector<BusyFlag::Hold> worlds;
    for (const auto& s : sims_) worlds.push_back(s->busy().hold());
    std::vector<std::exception_ptr> errors(count);
    {
      py::gil_scoped_release release;
      const std::function<void(int, int)> work = [&](int k, int) {
        try {
          f(static_cast<std::size_t>(k));
        } catch (...) {
          errors[static_cast<std::size_t>(k)] = std::current_exception();
        }
      };
      pool_->run(static_cast<int>(count), work);
    }
    for (const auto& e : errors)
      if (e) std::rethrow_exception(e);
  }

  std::vector<std::shared_ptr<Simulation>> sims_;
  std::size_t max_people_ = 0;
  BusyFlag busy_{"this hunav.VectorSimulation"};
  std::unique_ptr<hunav::ThreadPool> pool_;  // last: its threads stop before the worlds go
};

PYBIND11_MODULE(_hunav, m) {
  m.doc() = "HuNav-LCM's simulation in process (python/README.md)";
  // A bad scenario, agents or behavior-tree file; the message is "file:line: key: what".
  static py::exception<hunav::ConfigError> config_error(m, "ConfigError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const hunav::ConfigError& e) {
      config_error(e.what());
    } catch (const hunav::BadMessage& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::invalid_argument& e) {  // a logic_error too: caught first
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const std::logic_error& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  m.def("planners", &hunav::planners::plannerNames, "names of the built-in planners");
  py::class_<Simulation, std::shared_ptr<Simulation>>(m, "Simulation")
      .def(py::init<std::string, std::optional<long long>, std::optional<std::string>, std::optional<double>,
                    std::optional<double>, std::string, std::string, std::string, std::optional<std::string>,
                    std::string, std::string, std::string, bool, bool, bool, bool, std::optional<std::string>>(),
           py::arg("scenario"), py::arg("seed") = py::none(), py::arg("planner") = py::none(),
           py::arg("duration") = py::none(), py::arg("sample_rate") = py::none(), py::arg("planner_config") = "",
           py::arg("profile") = "default", py::arg("out_dir") = "", py::arg("experiment_tag") = py::none(),
           py::arg("run_id") = "", py::arg("metrics") = "", py::arg("format") = "csv",
           py::arg("evaluator_thread") = true, py::arg("states_csv") = true, py::arg("per_tick_files") = true,
           py::arg("files") = true, py::arg("people_model") = py::none())
      .def("reset", &Simulation::reset, py::arg("seed") = py::none(), py::arg("out_dir") = py::none())
      .def("step", &Simulation::step, py::arg("v"), py::arg("w"), py::arg("vy") = 0.0)
      .def("run", &Simulation::run)
      .def("observation", &Simulation::observation)
      .def("info", &Simulation::info)
      .def("state", &Simulation::state)
      .def("metrics", &Simulation::metrics)
      .def("positions", &Simulation::positions)
      .def("robot_frame_observation", &Simulation::robotFrameObservation, py::arg("max_people"), py::arg("range_max"))
      .def("reward_terms", &Simulation::rewardTerms, py::arg("personal_distance"))
      .def("fingerprint", &Simulation::fingerprint)
      .def("save", &Simulation::save, py::arg("out_dir"))
      .def("end_episode", &Simulation::endEpisode, py::arg("status"), py::arg("reason"))
      .def("map", &Simulation::mapDict)
      .def("occupancy_grid", &Simulation::occupancyGridDict)
      .def_property_readonly("robot", &Simulation::robotDict)
      .def_property_readonly("done", &Simulation::done)
      .def_property_readonly("planner", &Simulation::planner)
      .def_property_readonly("scenario_name", [](const Simulation& s) { return s.scenario().name; })
      .def_property_readonly("people_model", [](const Simulation& s) { return hunav::peopleModelLabel(s.scenario()); })
      .def_property_readonly("seed", [](const Simulation& s) { return s.scenario().seed; })
      .def_property_readonly("dt", [](const Simulation& s) { return s.scenario().dt; })
      .def_property_readonly("time_limit", [](const Simulation& s) { return s.scenario().time_limit; })
      .def_property_readonly("sample_rate", &Simulation::sampleRate)
      .def_property_readonly("experiment_tag", &Simulation::experimentTag)
      .def_property_readonly("metrics_file", &Simulation::metricsFile);

  py::class_<VectorSimulation>(m, "VectorSimulation")
      .def(py::init<int, std::string, std::optional<std::vector<long long>>, std::optional<std::string>,
                    std::optional<int>, std::optional<int>, std::optional<double>, std::optional<double>, std::string,
                    std::string, std::optional<std::string>, std::string, std::string, bool, bool, bool, bool>(),
           py::arg("n"), py::arg("scenario"), py::arg("seeds") = py::none(), py::arg("planner") = py::none(),
           py::arg("threads") = py::none(), py::arg("max_people") = py::none(), py::arg("duration") = py::none(),
           py::arg("sample_rate") = py::none(), py::arg("planner_config") = "", py::arg("profile") = "default",
           py::arg("experiment_tag") = py::none(), py::arg("metrics") = "", py::arg("format") = "csv",
           py::arg("evaluator_thread") = false, py::arg("states_csv") = true, py::arg("per_tick_files") = true,
           py::arg("files") = true)
      .def("reset", &VectorSimulation::reset, py::arg("seeds") = py::none(), py::arg("indices") = py::none(),
           py::arg("out_dirs") = py::none())
      .def("step", &VectorSimulation::step, py::arg("actions"))
      .def("run", &VectorSimulation::run)
      .def("observation", &VectorSimulation::observation)
      .def("state", &VectorSimulation::state)
      .def("robot_frame_observation", &VectorSimulation::robotFrameObservation, py::arg("max_people"),
           py::arg("range_max"))
      .def("reward_terms", &VectorSimulation::rewardTerms, py::arg("personal_distance"))
      .def("infos", &VectorSimulation::infos)
      .def("metrics", &VectorSimulation::metrics)
      .def("fingerprints", &VectorSimulation::fingerprints)
      .def("world", &VectorSimulation::world, py::arg("i"))
      .def("__getitem__", &VectorSimulation::world, py::arg("i"))
      .def("__len__", &VectorSimulation::size)
      .def_property_readonly("num_worlds", &VectorSimulation::size)
      .def_property_readonly("threads", &VectorSimulation::threads)
      .def_property_readonly("max_people", &VectorSimulation::maxPeople)
      .def_property_readonly("done", &VectorSimulation::done)
      .def_property_readonly("time", &VectorSimulation::times)
      .def_property_readonly("status", &VectorSimulation::status)
      .def_property_readonly("seeds", &VectorSimulation::seeds)
      .def_property_readonly("robot", [](const VectorSimulation& v) { return v.world(0)->robotDict(); })
      .def_property_readonly("dt", [](const VectorSimulation& v) { return v.world(0)->scenario().dt; })
      .def_property_readonly("time_limit", [](const VectorSimulation& v) { return v.world(0)->scenario().time_limit; });
}
