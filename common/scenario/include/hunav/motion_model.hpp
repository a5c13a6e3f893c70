#pragma once
// The people's model and its parameters, chosen by name or by file (docs/people_models.md): `sfm`
// (HuNavSim's social force model, the default), `orca`, `ttc`, and the parameter sets fitted on real
// pedestrians by `hunav_realism --calibrate`, shipped in common/people_model/motion_models/ and compiled in
// (`sfm_calibrated`, `orca_calibrated`, `ttc_calibrated`, and one per held-out scene,
// `<model>_calibrated_held_out_<scene>`). A parameter file is a YAML mapping `model: sfm|orca|ttc`
// plus the keys of that model (motionModelKeys); a key left out keeps its default.
#include <string>
#include <vector>

#include "hunav/orca.hpp"
#include "hunav/social_force.hpp"
#include "hunav/ttc_force.hpp"

namespace hunav {

enum class MotionModelKind { Sfm, Orca, Ttc };
const char* motionModelKindName(MotionModelKind kind);

struct MotionModel {
  std::string name = "sfm";  // the preset's name, or the file it was read from
  MotionModelKind kind = MotionModelKind::Sfm;
  // HuNavSim's SFM: each person's goal, obstacle and social weights come from its agents entry
  // (behavior_params); every other preset states all its parameters.
  bool weights_from_agents = true;
  SfmParams sfm;                   // SFM; the group weights act in every model that has groups (SFM, TTC)
  double interaction_range = 8.0;  // m, SFM: people farther away exert no social force (at most 8)
  OrcaParams orca;
  TtcParams ttc;
  // hunav_realism only: a recorded person's desired speed is this factor times its mean observed
  // speed (the simulator takes desired speeds from the scenario).
  double desired_speed_factor = 1.0;

  // HuNavSim's model with HuNavSim's parameters (the simulator's default).
  bool isHunavDefault() const { return kind == MotionModelKind::Sfm && weights_from_agents; }
};

// The preset names: sfm, orca, ttc, then the shipped parameter files' names in name order.
std::vector<std::string> motionModelNames();
// Whether `name` is one of them.
bool isMotionModelName(const std::string& name);
// A preset by name; throws ConfigError("", 0, key, ...) naming the known ones when there is none.
MotionModel motionModelByName(const std::string& name, const std::string& key = "people_model");

// Reads a parameter file. Unknown keys, keys of another model, values out of range (the ranges of
// motionModelKeys) and a missing `model` are ConfigErrors naming file, line and key.
MotionModel readMotionModel(const std::string& path);
// The same from YAML text (`file` names it in messages).
MotionModel parseMotionModel(const std::string& yaml, const std::string& file);
// A preset name, else a parameter file (a relative path taken from `base_dir` when it is not empty).
// Errors are ConfigErrors naming `file`:`line`: `key`.
MotionModel resolveMotionModel(const std::string& name_or_file, const std::string& base_dir, const std::string& file,
                               int line, const std::string& key);

// One parameter of a model: its key, its range and where it lives.
struct MotionModelKey {
  const char* key;
  double lo, hi;                         // the accepted range, both ends included
  double MotionModel::*field = nullptr;  // a member of MotionModel itself, or
  double SfmParams::*sfm = nullptr;      // of its sfm, orca or ttc parameters
  double OrcaParams::*orca = nullptr;
  double TtcParams::*ttc = nullptr;
  int OrcaParams::*orca_count = nullptr;  // an integer (max_neighbors)
  double get(const MotionModel& m) const;
  void set(MotionModel& m, double v) const;
};
// The keys a file of this model may hold (besides `model`).
const std::vector<MotionModelKey>& motionModelKeys(MotionModelKind kind);

// The file text of a model: `model:` and every key of its kind with its value (round trip exact:
// 17 significant digits), after `comment` lines (each prefixed with "# ").
std::string motionModelYaml(const MotionModel& m, const std::vector<std::string>& comment = {});

}  // namespace hunav
