#pragma once
// The realism score of the human model (realism/README.md): every person seen in 20 consecutive
// frames of a data set is a sample; from its state at the 8th frame the manager's social force model
// predicts the next 12 frames, the other people moving as recorded, and the prediction is compared
// with the record (ADE, FDE) next to a constant-velocity baseline on the same samples.
#include <array>
#include <string>
#include <vector>

#include "hunav/realism/tracks.hpp"

namespace hunav::realism {

inline constexpr int kObserved = 8;
inline constexpr int kPredicted = 12;
inline constexpr int kWindow = kObserved + kPredicted;

// The parameters of the model being scored. Defaults: HuNavSim's (goal 2, obstacle 10, social 5;
// radius 0.35 m and goal radius 0.3 m of a scenario's person; the manager's 0.01 s step and 8 m
// social cut-off); desired speed from the data (the person's mean observed speed).
struct ModelParams {
  double goal_weight = 2.0;
  double obstacle_weight = 10.0;  // no static obstacles in the data: listed for completeness
  double social_weight = 5.0;
  double desired_speed = -1.0;  // m/s; < 0: the person's mean speed over its 8 observed frames
  double radius = 0.35;         // m, every person's
  double goal_radius = 0.3;     // m
  double dt = 0.01;             // s, simulation step (a frame interval is split into equal steps <= dt)
  double cutoff = 8.0;          // m, people farther than this exert no social force (<= 0: all)
  double goal_distance = 2.0;   // extrapolated goal: this many prediction horizons ahead at the last velocity
};

// Reads ModelParams from a YAML mapping (keys as the struct's members); unknown keys and bad values
// are ConfigErrors naming file, line and key. Keys not present keep the value of `base`.
ModelParams readParams(const std::string& path, const ModelParams& base);

struct Sample {
  int id = 0;
  std::int64_t first_frame = 0;  // frame index of the first observed frame
  std::array<Vec2, kWindow> truth{};
};

// Every (person, first frame) with the person present in all 20 consecutive frames (a sliding window,
// stride one frame: the usual ETH/UCY protocol).
std::vector<Sample> extractSamples(const Dataset& d);

using Prediction = std::array<Vec2, kPredicted>;
// Mean and final displacement errors of the 12 predicted positions against truth[8..19].
double ade(const Prediction& pred, const Sample& s);
double fde(const Prediction& pred, const Sample& s);

// The last observed velocity (truth[7] - truth[6]) / interval, kept for 12 frames.
Prediction predictConstantVelocity(const Sample& s, double interval);

enum class GoalMode {
  Extrapolated,  // truth[7] + last velocity * goal_distance * 12 intervals
  Oracle         // the true position at the 20th frame
};
// The manager's social force model (hunav::manager::computeForces, the force RegularNav moves people
// with, and hunav::integrate) from truth[7] with the last observed velocity toward the goal of `mode`;
// the other people of the data set at their recorded positions, linearly interpolated between frames,
// with the velocity of the frame interval.
Prediction predictSocialForce(const Dataset& d, const Sample& s, const ModelParams& p, GoalMode mode);
double desiredSpeedOf(const Sample& s, double interval, const ModelParams& p);
Vec2 goalOf(const Sample& s, double interval, const ModelParams& p, GoalMode mode);

// Distance from `p` to the nearest person other than `id` recorded in frame `frame` (< 0: nobody).
double nearestNeighbour(const Dataset& d, std::int64_t frame, int id, const Vec2& p);

struct Distribution {
  std::vector<double> values;  // sorted
  double mean() const;
  double quantile(double q) const;  // linear interpolation between order statistics
};
// 1-Wasserstein (earth mover's) distance between two empirical distributions (same unit as the values).
double wasserstein1(const Distribution& a, const Distribution& b);

struct MethodResult {
  std::string method;  // cv, sfm, sfm_oracle
  double ade = 0.0, fde = 0.0;
  Distribution speed;  // m/s over the 12 predicted frame intervals
  Distribution nn;     // m, nearest recorded neighbour at the 12 predicted frames
};

inline constexpr int kMethods = 3;
inline const char* const kMethodNames[kMethods] = {"cv", "sfm", "sfm_oracle"};

struct SampleResult {
  int id = 0;
  std::int64_t first_frame = 0;
  double ade[kMethods] = {}, fde[kMethods] = {};  // in kMethodNames order
};

struct DatasetResult {
  std::string name, path;
  double frame_interval = 0.4;
  std::size_t samples = 0;
  std::vector<SampleResult> per_sample;
  MethodResult data;                  // the record's own speed and nn distributions
  std::vector<MethodResult> methods;  // in kMethodNames order
  double seconds = 0.0;               // wall clock of the evaluation
};

DatasetResult evaluate(const Dataset& d, const ModelParams& p);

}  // namespace hunav::realism
