#include "hunav/realism/scoring.hpp"

#include <filesystem>
#include <set>

#include "hunav/config_error.hpp"

namespace hunav::realism {

MotionModel uncalibratedModel(const Scoring& scoring, const std::string& family) {
  MotionModel m = motionModelByName(family);
  if (family == "sfm") {
    m.sfm.goal_weight = scoring.hunav_sfm.goal_weight;
    m.sfm.obstacle_weight = scoring.hunav_sfm.obstacle_weight;
    m.sfm.social_weight = scoring.hunav_sfm.social_weight;
  }
  return m;
}

std::string calibratedName(const std::string& family, const std::string& held_out) {
  return family + "_calibrated" + (held_out.empty() ? "" : "_held_out_" + held_out);
}

std::optional<MotionModel> calibratedModel(const Scoring& scoring, const std::string& family,
                                           const std::string& scene) {
  for (const std::string& name : {calibratedName(family, scene), calibratedName(family)}) {
    if (!scoring.calibrated_dir.empty()) {
      const std::filesystem::path file = std::filesystem::path(scoring.calibrated_dir) / (name + ".yaml");
      std::error_code ec;
      if (std::filesystem::is_regular_file(file, ec)) {
        MotionModel m = readMotionModel(file.string());
        m.name = name;
        return m;
      }
    } else if (isMotionModelName(name)) {
      return motionModelByName(name);
    }
  }
  return std::nullopt;
}

bool hasGroupTerms(const std::string& family) { return family != "orca"; }

std::vector<Method> methodsOf(const std::string& prefix, const MotionModel& model, bool groups) {
  std::vector<Method> out;
  auto add = [&](const std::string& suffix, GoalMode goal, bool interaction, bool with_groups) {
    Method m;
    m.name = prefix + suffix;
    m.model = model;
    m.goal = goal;
    m.interaction = interaction;
    m.groups = with_groups;
    out.push_back(m);
  };
  add("", GoalMode::Extrapolated, true, false);
  add("_goal", GoalMode::Recorded, true, false);
  add("_goal_alone", GoalMode::Recorded, false, false);
  if (groups) add("_goal_groups", GoalMode::Recorded, true, true);
  return out;
}

std::vector<DatasetResult> scoreAll(const std::vector<Dataset>& sets, const Scoring& scoring, ThreadPool* threads,
                                    std::ostream& log, std::vector<ModelSummary>& models) {
  Method cv;
  cv.name = "cv";
  cv.constant_velocity = true;
  std::set<std::string> listed;
  auto summarise = [&](const MotionModel& m) {
    if (listed.insert(m.name).second) models.push_back(ModelSummary{m.name, motionModelYaml(m)});
  };
  std::vector<DatasetResult> results;
  for (const Dataset& d : sets) {
    const GroupIds groups = scoring.groups ? detectGroups(d) : GroupIds{};
    for (const char* split : {"all", "test"}) {
      const bool test = std::string(split) == "test";
      if ((test && !scoring.split_test) || (!test && !scoring.split_all)) continue;
      std::vector<Method> methods = {cv};
      for (const std::string& family : scoring.families) {
        std::optional<MotionModel> model = test ? calibratedModel(scoring, family, d.name)
                                                : std::optional<MotionModel>(uncalibratedModel(scoring, family));
        if (!model) {
          log << "hunav_realism: " << d.name << ": no calibrated parameters of " << family << " (neither "
              << calibratedName(family, d.name) << " nor " << calibratedName(family)
              << "): its test columns are left out (--calibrate fits them)\n";
          continue;
        }
        summarise(*model);
        for (const Method& m :
             methodsOf(test ? calibratedName(family) : family, *model, scoring.groups && hasGroupTerms(family)))
          methods.push_back(m);
      }
      DatasetResult r = evaluate(d, methods, scoring.protocol, &groups, threads);
      r.split = split;
      log << "hunav_realism: " << d.name << " (" << split << "): " << r.samples << " samples, " << methods.size()
          << " methods in " << r.seconds << " s\n";
      results.push_back(std::move(r));
    }
  }
  return results;
}

}  // namespace hunav::realism
