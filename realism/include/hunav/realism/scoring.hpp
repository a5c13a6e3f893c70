#pragma once
// Which columns hunav_realism scores and with which parameters (realism/README.md, "Methods"): per
// data set, split `all` (every family with its own parameters: M, M_goal, M_goal_alone,
// M_goal_groups) and split `test` (the calibrated parameters fitted without that data set:
// M_calibrated, M_calibrated_goal, ...), each with the constant-velocity baseline `cv`.
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "hunav/realism/output.hpp"
#include "hunav/realism/realism.hpp"

namespace hunav::realism {

struct Scoring {
  Protocol protocol;
  SfmParams hunav_sfm;  // the weights of the `sfm` columns (HuNavSim's by default)
  std::vector<std::string> families = {"sfm", "orca", "ttc"};
  bool split_all = true, split_test = true;
  bool groups = true;  // also the _groups columns (families with group terms: sfm, ttc)
  std::string
      calibrated_dir;  // the calibrated parameter files; empty: the shipped ones (common/people_model/motion_models)
};

// The family's model with its own parameters: `sfm` HuNavSim's (with scoring.hunav_sfm's weights),
// `orca` and `ttc` their defaults.
MotionModel uncalibratedModel(const Scoring& scoring, const std::string& family);
// The name of a calibrated parameter set: <family>_calibrated (fitted on every scene) or
// <family>_calibrated_held_out_<scene>.
std::string calibratedName(const std::string& family, const std::string& held_out = "");
// The calibrated model to score data set `scene` with: the one fitted without it, else the one fitted on
// every scene (then `scene` was not among them either); from scoring.calibrated_dir or the shipped
// files. None when neither exists.
std::optional<MotionModel> calibratedModel(const Scoring& scoring, const std::string& family, const std::string& scene);
// The columns of one model: `prefix` (extrapolated goal), prefix_goal, prefix_goal_alone and, with
// groups, prefix_goal_groups.
std::vector<Method> methodsOf(const std::string& prefix, const MotionModel& model, bool groups);
// Whether the family's model has group terms (SFM and TTC; ORCA has none).
bool hasGroupTerms(const std::string& family);

// Scores every data set (and split) and returns the results in data set order, `all` before `test`;
// `models` receives the parameter sets used (name and file text). Progress lines go to `log`.
std::vector<DatasetResult> scoreAll(const std::vector<Dataset>& sets, const Scoring& scoring, ThreadPool* threads,
                                    std::ostream& log, std::vector<ModelSummary>& models);

}  // namespace hunav::realism
