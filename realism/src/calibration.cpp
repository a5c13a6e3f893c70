#include "hunav/realism/calibration.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlopt.hpp>
#include <stdexcept>

#include "hunav/config_error.hpp"

namespace hunav::realism {

namespace {

const MotionModelKey& keyOf(MotionModelKind kind, const std::string& name) {
  for (const MotionModelKey& k : motionModelKeys(kind))
    if (name == k.key) return k;
  throw std::logic_error("no parameter " + name);
}

bool isGroupWeight(const char* key) { return std::string(key).rfind("group_", 0) == 0; }

const char* stopReason(nlopt::result r) {
  switch (r) {
    case nlopt::MAXEVAL_REACHED:
      return "the evaluation budget was used";
    case nlopt::XTOL_REACHED:
      return "the parameters converged (xtol)";
    case nlopt::FTOL_REACHED:
      return "the objective converged (ftol)";
    case nlopt::SUCCESS:
      return "NLopt reported success";
    default:
      return "NLopt stopped";
  }
}

}  // namespace

double FreeParameter::at(double x) const {
  x = std::clamp(x, 0.0, 1.0);
  return log_scale ? lo * std::pow(hi / lo, x) : lo + x * (hi - lo);
}

double FreeParameter::fraction(double v) const {
  const double x = log_scale ? std::log(std::max(v, lo) / lo) / std::log(hi / lo) : (v - lo) / (hi - lo);
  return std::clamp(x, 0.0, 1.0);
}

const std::vector<FreeParameter>& freeParameters(MotionModelKind kind) {
  static const std::vector<FreeParameter> sfm = {{"goal_weight", 0.1, 10.0},
                                                 {"social_weight", 0.0, 20.0},
                                                 {"lambda", 0.0, 5.0},
                                                 {"gamma", 0.05, 2.0},
                                                 {"n", 0.2, 6.0},
                                                 {"n_prime", 0.2, 8.0},
                                                 {"relaxation_time", 0.1, 2.0},
                                                 {"interaction_range", 0.5, 8.0},
                                                 {"group_gaze_weight", 0.0, 10.0},
                                                 {"group_coherence_weight", 0.0, 10.0},
                                                 {"group_repulsion_weight", 0.0, 10.0},
                                                 {"desired_speed_factor", 0.7, 1.5}};
  static const std::vector<FreeParameter> orca = {
      {"neighbor_distance", 0.5, 10.0}, {"time_horizon", 0.1, 10.0},   {"radius", 0.05, 0.5},
      {"responsibility", 0.05, 1.0},    {"relaxation_time", 0.0, 2.0}, {"desired_speed_factor", 0.7, 1.5}};
  // TTC's tau0 stays near the paper's 3 s, and its force cap spans gentle to violent on a log scale
  // (realism/README.md, "Calibration": why both).
  static const std::vector<FreeParameter> ttc = {{"k", 0.0, 10.0},
                                                 {"tau0", 0.2, 5.0},
                                                 {"relaxation_time", 0.05, 2.0},
                                                 {"radius", 0.05, 0.5},
                                                 {"neighbor_distance", 0.5, 10.0},
                                                 {"max_force", 0.05, 50.0, true},
                                                 {"field_of_view", kPi / 2.0, 2.0 * kPi},
                                                 {"max_speed_factor", 1.0, 1.5},
                                                 {"speed_share", 0.0, 1.0},
                                                 {"group_gaze_weight", 0.0, 10.0},
                                                 {"group_coherence_weight", 0.0, 10.0},
                                                 {"group_repulsion_weight", 0.0, 10.0},
                                                 {"desired_speed_factor", 0.7, 1.5}};
  return kind == MotionModelKind::Orca ? orca : (kind == MotionModelKind::Ttc ? ttc : sfm);
}

TrainingScene trainingScene(const Dataset& d, std::size_t samples, bool groups) {
  TrainingScene t;
  t.data = &d;
  const std::vector<Sample> all = extractSamples(d);
  const std::size_t n = std::min(samples, all.size());
  // Evenly spaced over the recording: sample i * |all| / n (deterministic, spans the whole scene).
  for (std::size_t i = 0; i < n; ++i) t.samples.push_back(all[i * all.size() / n]);
  if (groups) t.groups = detectGroups(d);
  return t;
}

double calibrationObjective(const std::vector<TrainingScene>& scenes, const MotionModel& model, const Protocol& p,
                            bool groups, double overlap_penalty, ThreadPool* threads) {
  Method m;
  m.name = "fit";
  m.model = model;
  m.goal = GoalMode::Recorded;
  m.groups = groups;
  double sum = 0.0;
  for (const TrainingScene& t : scenes) {
    const DatasetResult r = evaluate(*t.data, {m}, p, &t.groups, threads, &t.samples);
    // Real people come that close too, now and then: only overlaps beyond the data's own share cost.
    sum += r.methods[0].ade + overlap_penalty * std::max(0.0, r.methods[0].overlaps - r.data.overlaps);
  }
  return scenes.empty() ? 0.0 : sum / static_cast<double>(scenes.size());
}

FitResult fitModel(const std::vector<TrainingScene>& scenes, const MotionModel& start, const Protocol& p,
                   FitStage stage, const CalibrationOptions& options, ThreadPool* threads) {
  const auto clock_start = std::chrono::steady_clock::now();
  const bool groups = stage == FitStage::Groups;
  std::vector<FreeParameter> free;
  for (const FreeParameter& f : freeParameters(start.kind))
    if (groups == isGroupWeight(f.key)) free.push_back(f);
  const int budget = groups ? std::max(10, options.max_evaluations / 3) : options.max_evaluations;
  const std::size_t n = free.size();
  // The search runs on x in [0, 1]^n (value = FreeParameter::at(x)): BOBYQA's trust region is one radius
  // for every coordinate, so the coordinates must share a scale.
  auto modelAt = [&](const std::vector<double>& x) {
    MotionModel m = start;
    for (std::size_t i = 0; i < n; ++i) keyOf(start.kind, free[i].key).set(m, free[i].at(x[i]));
    return m;
  };
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = free[i].fraction(keyOf(start.kind, free[i].key).get(start));
  }
  FitResult result;
  result.model = start;
  result.start_objective = calibrationObjective(scenes, result.model, p, groups, options.overlap_penalty, threads);
  result.best_objective = result.start_objective;
  result.evaluations = 1;

  struct State {
    FitResult* result;
    decltype(modelAt)* model_at;
    const std::vector<TrainingScene>* scenes;
    const Protocol* p;
    bool groups;
    double penalty;
    ThreadPool* threads;
  } state{&result, &modelAt, &scenes, &p, groups, options.overlap_penalty, threads};
  auto objective = [](const std::vector<double>& at, std::vector<double>&, void* data) {
    State& s = *static_cast<State*>(data);
    const MotionModel m = (*s.model_at)(at);
    const double value = calibrationObjective(*s.scenes, m, *s.p, s.groups, s.penalty, s.threads);
    s.result->evaluations += 1;
    if (value < s.result->best_objective) {
      s.result->best_objective = value;
      s.result->model = m;
    }
    return value;
  };
  // BOBYQA from several starts, the budget each: the objective has several basins (with a large radius
  // the interaction only hurts and the fit switches it off, where radius and range no longer matter;
  // from there no local step finds the basin of a small radius). The starts: the model's own
  // parameters, and every free parameter a quarter and three quarters into its box.
  std::vector<std::vector<double>> starts = {x};
  if (stage == FitStage::Interaction)
    for (double at : {0.25, 0.75}) starts.emplace_back(n, at);
  std::vector<std::string> stops;
  for (std::vector<double>& from : starts) {
    nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(n));
    opt.set_lower_bounds(std::vector<double>(n, 0.0));
    opt.set_upper_bounds(std::vector<double>(n, 1.0));
    opt.set_min_objective(objective, &state);
    opt.set_maxeval(std::max(1, budget - (&from == &starts.front() ? 1 : 0)));  // the first start was one
    opt.set_initial_step(0.15);
    opt.set_xtol_rel(1e-4);
    double value = 0.0;
    try {
      stops.push_back(stopReason(opt.optimize(from, value)));
    } catch (const nlopt::roundoff_limited&) {
      stops.push_back("NLopt stopped: round-off limited");
    } catch (const std::invalid_argument& e) {
      stops.push_back(std::string("NLopt refused: ") + e.what());
    }
  }
  for (const std::string& stop : stops) result.stop += (result.stop.empty() ? "" : "; ") + stop;
  if (!result.improved()) {
    result.model = start;  // nothing better: the start, as it was
    result.best_objective = result.start_objective;
  }
  result.model.name = start.name;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  return result;
}

void calibrateAll(const std::vector<Dataset>& sets, const Scoring& scoring, const CalibrationOptions& options,
                  const std::string& dir, ThreadPool* threads, std::ostream& log) {
  std::filesystem::create_directories(dir);
  std::vector<TrainingScene> scenes;
  for (const Dataset& d : sets) scenes.push_back(trainingScene(d, options.samples_per_scene, scoring.groups));
  std::string csv =
      "model,held_out,stage,scenes,samples_per_scene,start_objective,best_objective,improved,evaluations,seconds,"
      "stop\n";
  for (const std::string& family : scoring.families) {
    MotionModel start = uncalibratedModel(scoring, family);
    start.weights_from_agents = false;  // every parameter of the fit is the file's
    // "The person's own radius" is the protocol's: where the search starts.
    if (start.orca.radius < 0.0) start.orca.radius = scoring.protocol.radius;
    if (start.ttc.radius < 0.0) start.ttc.radius = scoring.protocol.radius;
    const bool groups = scoring.groups && hasGroupTerms(family);
    // Held out in turn (with two or more sets), then all of them.
    std::vector<std::string> held_out;
    if (sets.size() >= 2)
      for (const Dataset& d : sets) held_out.push_back(d.name);
    held_out.push_back("");
    if (!options.folds.empty()) {
      held_out.clear();
      for (const std::string& f : options.folds) {
        const bool known =
            f == "none" || std::any_of(sets.begin(), sets.end(), [&](const Dataset& d) { return d.name == f; });
        if (!known) throw ConfigError("", 0, "--folds", "'" + f + "' is neither a data set's name nor none");
        held_out.push_back(f == "none" ? "" : f);
      }
    }
    for (const std::string& out : held_out) {
      std::vector<TrainingScene> train;
      std::string names;
      for (const TrainingScene& t : scenes)
        if (t.data->name != out) {
          train.push_back(t);
          names += (names.empty() ? "" : " ") + t.data->name;
        }
      const std::string name = calibratedName(family, out);
      start.name = name;
      log << "hunav_realism: calibrating " << name << " on " << names << " ...\n";
      // Stage 1: the interaction (everything but the group weights) on the goal-conditioned column
      // without groups; stage 2: the group weights, the rest fixed, with the detected groups.
      std::vector<FitResult> fits = {fitModel(train, start, scoring.protocol, FitStage::Interaction, options, threads)};
      if (groups) fits.push_back(fitModel(train, fits[0].model, scoring.protocol, FitStage::Groups, options, threads));
      std::vector<std::string> comment = {
          fmt::format("{}: {} fitted by hunav_realism --calibrate (realism/README.md, \"Calibration\")", name, family),
          fmt::format("training scenes: {} ({} evenly spaced samples each); objective: the mean over the scenes of "
                      "goal-conditioned ADE + {:g} m x the overlap share beyond the data's",
                      names, options.samples_per_scene, options.overlap_penalty)};
      for (std::size_t k = 0; k < fits.size(); ++k) {
        const FitResult& fit = fits[k];
        const char* stage = k == 0 ? "interaction" : "group weights";
        const std::string what =
            fit.improved() ? fmt::format("objective {:.6f} -> {:.6f} m", fit.start_objective, fit.best_objective)
                           : fmt::format("could not improve on its start (objective {:.6f} m): the start's parameters",
                                         fit.start_objective);
        log << fmt::format("hunav_realism: {}: {}: {} in {} evaluations, {:.0f} s ({})\n", name, stage, what,
                           fit.evaluations, fit.seconds, fit.stop);
        comment.push_back(fmt::format("{} ({}): {}; NLopt LN_BOBYQA, {} evaluations, {}; {:.0f} s", stage,
                                      k == 0 ? "without groups" : "with the detected groups", what, fit.evaluations,
                                      fit.stop, fit.seconds));
        csv += fmt::format("{},{},{},{},{},{:.6f},{:.6f},{},{},{:.1f},{}\n", family, out.empty() ? "none" : out,
                           k == 0 ? "interaction" : "groups", names, options.samples_per_scene, fit.start_objective,
                           fit.best_objective, fit.improved() ? "yes" : "no", fit.evaluations, fit.seconds, fit.stop);
      }
      const std::filesystem::path file = std::filesystem::path(dir) / (name + ".yaml");
      std::ofstream f(file);
      f << motionModelYaml(fits.back().model, comment);
      if (!f) throw std::runtime_error("cannot write " + file.string());
    }
  }
  std::ofstream f(std::filesystem::path(dir) / "calibration.csv");
  f << csv;
}

}  // namespace hunav::realism
