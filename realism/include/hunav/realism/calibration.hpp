#pragma once
// hunav_realism --calibrate (realism/README.md, "Calibration"): fits a people model's parameters to
// real pedestrians with NLopt's BOBYQA (derivative-free, bounded, deterministic): the objective is
// the goal-conditioned ADE (the model walking to the person's recorded position at the 20th frame
// among the others as recorded) plus a penalty on overlaps, averaged over the training scenes, on
// evenly spaced samples of each, within a fixed number of evaluations; first the interaction, then
// the group weights with the detected groups.
#include <ostream>
#include <string>
#include <vector>

#include "hunav/realism/realism.hpp"
#include "hunav/realism/scoring.hpp"

namespace hunav::realism {

struct CalibrationOptions {
  int max_evaluations = 60;              // objective evaluations per start of a fit (the time bound: no wall
                                         // clock, so the result does not depend on the machine)
  std::size_t samples_per_scene = 1000;  // evenly spaced samples of each training scene
  double overlap_penalty = 1.0;          // m of ADE per unit of overlap share beyond the data's
  // The fits to make: data set names to hold out, "none" for the fit on all of them; empty: each
  // data set in turn (with two or more) and none.
  std::vector<std::string> folds;
};

// A parameter the calibration fits, and the box it searches (within the parameter file's range).
struct FreeParameter {
  const char* key;
  double lo, hi;
  // Searched on a log scale (lo > 0): for a bound spanning orders of magnitude, where 0.5 and 1 differ
  // as much as 20 and 40.
  bool log_scale = false;
  double at(double x) const;        // the value a fraction x in [0, 1] into the box
  double fraction(double v) const;  // its inverse, clamped to [0, 1]
};
// The parameters fitted for a model kind (realism/README.md lists them, and why the others are not).
const std::vector<FreeParameter>& freeParameters(MotionModelKind kind);

// A training scene: its samples used by the objective (evenly spaced) and its groups.
struct TrainingScene {
  const Dataset* data = nullptr;
  std::vector<Sample> samples;
  GroupIds groups;
};
TrainingScene trainingScene(const Dataset& d, std::size_t samples, bool groups);

// The objective of a model on the scenes: the mean over the scenes of ADE + penalty * (overlap share
// of its goal-conditioned column (with groups when `groups`) beyond the data's own share, if any).
double calibrationObjective(const std::vector<TrainingScene>& scenes, const MotionModel& model, const Protocol& p,
                            bool groups, double overlap_penalty, ThreadPool* threads);

struct FitResult {
  MotionModel model;  // the best parameters seen (the start's when nothing was better)
  double start_objective = 0.0, best_objective = 0.0;
  int evaluations = 0;
  double seconds = 0.0;
  std::string stop;  // why NLopt stopped
  // Better than the start by more than a micrometre (rounding differences are no improvement).
  bool improved() const { return best_objective < start_objective - 1e-6; }
};
// What one fit searches: the interaction (every free parameter but the group weights, on the
// goal-conditioned column without groups, within max_evaluations), or the group weights (the rest as
// `start` has them, with the detected groups, within max_evaluations / 3, at least 10).
enum class FitStage { Interaction, Groups };
FitResult fitModel(const std::vector<TrainingScene>& scenes, const MotionModel& start, const Protocol& p,
                   FitStage stage, const CalibrationOptions& options, ThreadPool* threads);

// Every family of scoring.families on every held-out scene (fitted on the others, when there are at
// least two sets) and on all of them: writes <family>_calibrated[_held_out_<scene>].yaml and
// calibration.csv into `dir`, progress into `log`. A fit that cannot improve on its start says so and
// writes the start's parameters.
void calibrateAll(const std::vector<Dataset>& sets, const Scoring& scoring, const CalibrationOptions& options,
                  const std::string& dir, ThreadPool* threads, std::ostream& log);

}  // namespace hunav::realism
