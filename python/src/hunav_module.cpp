// The `hunav` Python module: the in-process simulation (runner/stepped_run.hpp) stepped from Python,
// observations and ground truth as numpy arrays. python/README.md documents the API.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/evaluator/results.hpp"
#include "hunav/evaluator/sample_rate.hpp"
#include "hunav/message_checks.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/runner/stepped_run.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace {

using hunav::runner::SteppedRun;

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

}  // namespace

// Python's hunav.Simulation: loads the scenario once per seed and builds a SteppedRun per episode.
class Simulation {
 public:
  Simulation(std::string scenario_file, std::optional<long long> seed, std::optional<std::string> planner,
             std::optional<double> duration, std::optional<double> sample_rate, std::string planner_config,
             std::string profile, std::string out_dir, std::string experiment_tag, std::string run_id)
      : file_(std::move(scenario_file)),
        duration_(duration.value_or(0.0)),
        sample_rate_(sample_rate),
        keep_out_dir_(!out_dir.empty()) {
    if (seed && *seed < 0) throw std::invalid_argument("seed must be >= 0");
    if (sample_rate) hunav::evaluator::SampleRate{*sample_rate};  // the evaluator's own check
    // Without a built-in planner the robot is driven from Python, recorded as planner "python".
    external_ = !planner.has_value();
    options_.planner = planner.value_or("python");
    if (!external_ && options_.planner != "none" && !hunav::planners::hasPlanner(options_.planner))
      throw std::invalid_argument("unknown planner '" + options_.planner + "'");
    options_.planner_config = std::move(planner_config);
    options_.profile = std::move(profile);
    options_.out_dir = std::move(out_dir);
    options_.experiment_tag = std::move(experiment_tag);
    options_.run_id = std::move(run_id);
    load(seed.value_or(-1));  // a bad scenario raises here, before any reset()
  }
  ~Simulation() {
    run_.reset();
    removeTempDir();
  }

  py::dict reset(std::optional<long long> seed) {
    if (seed) {
      if (*seed < 0) throw std::invalid_argument("seed must be >= 0");
      if (static_cast<std::uint64_t>(*seed) != scenario_.seed) load(*seed);
    }
    run_.reset();
    removeTempDir();
    hunav::runner::RunOptions o = options_;
    if (o.out_dir.empty()) o.out_dir = (temp_dir_ = makeTempDir()).string();
    run_ = std::make_unique<SteppedRun>(scenario_, o, external_);
    {
      py::gil_scoped_release release;
      run_->start();
    }
    return observation();
  }

  py::dict step(double v, double w, double vy) {
    SteppedRun& r = started();
    if (!r.external()) throw std::logic_error("planner '" + options_.planner + "' drives the robot: use run()");
    if (r.ended()) throw std::logic_error("the episode has ended (" + r.episode().status + "): call reset()");
    for (const auto& [x, name] : {std::pair{v, "v"}, {w, "w"}, {vy, "vy"}})
      if (!std::isfinite(x)) throw std::invalid_argument(std::string(name) + " is not finite");
    if (vy != 0.0 && scenario_.robot.drive != hunav::RobotDrive::Holonomic)
      throw std::invalid_argument("vy is for a holonomic robot; this one has a differential drive");
    {
      py::gil_scoped_release release;
      r.step(v, vy, w);
    }
    return observation();
  }

  py::dict run() {
    if (!run_) reset(std::nullopt);
    {
      py::gil_scoped_release release;
      run_->finish();
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

  // Copies the episode's result files (metrics.csv, states.csv, run.json, ...) into out_dir.
  std::string save(const std::string& out_dir) const {
    const SteppedRun& r = started();
    if (!r.ended() || !r.outcome()->result)
      throw std::logic_error("the episode is still running: step() or run() it to the end first");
    const fs::path from = r.outcome()->result->metrics_csv.parent_path();
    fs::create_directories(out_dir);
    fs::copy(from, out_dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    return fs::path(out_dir).string();
  }

  py::dict mapDict() const { return mapOf(scenario_); }
  py::dict robotDict() const {
    const auto& rc = scenario_.robot;
    const auto& l = rc.limits;
    py::dict d;
    d["radius"] = rc.radius;
    d["holonomic"] = rc.drive == hunav::RobotDrive::Holonomic;
    d["max_v"] = l.max_v, d["min_v"] = l.min_v, d["max_w"] = l.max_w, d["max_vy"] = l.max_vy;
    d["max_acc_v"] = l.max_acc_v, d["max_acc_w"] = l.max_acc_w;
    d["control_period"] = std::max(1L, std::lround(1.0 / (rc.control_rate * scenario_.dt))) * scenario_.dt;
    d["laser_beams"] = rc.laser.beams, d["laser_fov"] = rc.laser.fov;
    d["laser_range_min"] = rc.laser.range_min, d["laser_range_max"] = rc.laser.range_max;
    d["start"] = doubles({rc.start.x(), rc.start.y(), rc.start_yaw});
    d["goal"] = doubles({rc.goal.x(), rc.goal.y(), rc.goal_yaw, rc.goal_radius});
    d["has_goal"] = rc.has_goal;
    return d;
  }
  const hunav::Scenario& scenario() const { return scenario_; }
  bool done() const { return run_ && run_->ended(); }
  std::string planner() const { return options_.planner; }

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

  void load(long long seed) {
    scenario_ = hunav::cli::loadScenarioFor(file_, seed, duration_);
    if (sample_rate_) scenario_.evaluation_sample_rate = *sample_rate_;
  }
  SteppedRun& started() const {
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
  double duration_;
  std::optional<double> sample_rate_;
  bool keep_out_dir_;
  bool external_ = false;
  hunav::runner::RunOptions options_;
  hunav::Scenario scenario_;
  fs::path temp_dir_;
  std::unique_ptr<SteppedRun> run_;
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
  py::class_<Simulation>(m, "Simulation")
      .def(py::init<std::string, std::optional<long long>, std::optional<std::string>, std::optional<double>,
                    std::optional<double>, std::string, std::string, std::string, std::string, std::string>(),
           py::arg("scenario"), py::arg("seed") = py::none(), py::arg("planner") = py::none(),
           py::arg("duration") = py::none(), py::arg("sample_rate") = py::none(), py::arg("planner_config") = "",
           py::arg("profile") = "default", py::arg("out_dir") = "", py::arg("experiment_tag") = "exp",
           py::arg("run_id") = "")
      .def("reset", &Simulation::reset, py::arg("seed") = py::none())
      .def("step", &Simulation::step, py::arg("v"), py::arg("w"), py::arg("vy") = 0.0)
      .def("run", &Simulation::run)
      .def("observation", &Simulation::observation)
      .def("info", &Simulation::info)
      .def("state", &Simulation::state)
      .def("metrics", &Simulation::metrics)
      .def("fingerprint", &Simulation::fingerprint)
      .def("save", &Simulation::save, py::arg("out_dir"))
      .def("map", &Simulation::mapDict)
      .def_property_readonly("robot", &Simulation::robotDict)
      .def_property_readonly("done", &Simulation::done)
      .def_property_readonly("planner", &Simulation::planner)
      .def_property_readonly("scenario_name", [](const Simulation& s) { return s.scenario().name; })
      .def_property_readonly("seed", [](const Simulation& s) { return s.scenario().seed; })
      .def_property_readonly("dt", [](const Simulation& s) { return s.scenario().dt; })
      .def_property_readonly("time_limit", [](const Simulation& s) { return s.scenario().time_limit; });
}
