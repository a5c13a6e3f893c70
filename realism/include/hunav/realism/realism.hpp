#pragma once
// The realism score of the people models (realism/README.md): every person seen in 20 consecutive
// frames of a data set is a sample; from its state at the 8th frame a model predicts the next 12
// frames, the other people moving as recorded, and the prediction is compared with the record (ADE,
// FDE, speed and nearest-neighbour distributions, overlaps) next to a constant-velocity baseline on
// the same samples. A model walks toward an extrapolated goal (the forecasting view) or toward the
// person's recorded position at the 20th frame (the simulator's view: a person with a goal).
#include <array>
#include <string>
#include <vector>

#include "hunav/motion_model.hpp"
#include "hunav/realism/groups.hpp"
#include "hunav/realism/tracks.hpp"

namespace hunav {
class ThreadPool;
}

namespace hunav::realism {

inline constexpr int kObserved = 8;
inline constexpr int kPredicted = 12;
inline constexpr int kWindow = kObserved + kPredicted;

// What the protocol fixes, whatever the model (realism/README.md, "Protocol").
struct Protocol {
  double radius = 0.35;  // m, every recorded person's body (a scenario person's default)
  // m; the recorded position is a point the person walks through, not where it stops: a goal radius
  // would stop the model short of it (0.3 m, HuNavSim's usual, is the floor of the final error then)
  double goal_radius = 0.0;
  double dt = 0.01;               // s, longest simulation step (a frame interval is split into equal steps)
  double cutoff = 8.0;            // m, HuNavSim's SFM: people farther than this exert no social force (<= 0: all)
  double goal_distance = 2.0;     // extrapolated goal: this many prediction horizons ahead at the last velocity
  double desired_speed = -1.0;    // m/s for everybody; < 0: the model's factor times the mean observed speed
  double overlap_distance = 0.3;  // m, a predicted position this close to a recorded person is an overlap
};

// Reads Protocol keys and HuNavSim-SFM weights (goal_weight, obstacle_weight, social_weight: the `sfm`
// columns' weights) from a YAML mapping; unknown keys and bad values are ConfigErrors naming file,
// line and key. Keys not present keep the values of `protocol` and `sfm`.
void readProtocol(const std::string& path, Protocol& protocol, SfmParams& sfm);

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
  Extrapolated,  // truth[7] + last velocity * goal_distance * 12 intervals (forecasting)
  Recorded       // the person's position at the 20th frame (a simulated person's goal)
};

// One column of the table: a model, where it walks, and whether the others count.
struct Method {
  std::string name;                // cv, sfm, sfm_goal, sfm_goal_alone, orca_calibrated_goal, ...
  bool constant_velocity = false;  // the baseline (the rest unused)
  MotionModel model;
  GoalMode goal = GoalMode::Extrapolated;
  bool interaction = true;  // false: the person walks alone (the "_alone" columns)
  bool groups = false;      // the model's group terms act on the detected groups
};

// The desired speed of a sample's person under `model`, and its goal.
double desiredSpeedOf(const Sample& s, double interval, const Protocol& p, const MotionModel& model);
Vec2 goalOf(const Sample& s, double interval, const Protocol& p, GoalMode mode);

// The method's prediction: the model's steps (hunav::manager::modelStep, what the manager moves
// people with) from truth[7] with the last observed velocity toward the goal, the others of the data
// set at their recorded positions, linearly interpolated between frames, with the velocity of the
// frame interval (recorded at both ends of it). `groups` (with method.groups) gives the group ids.
Prediction predict(const Dataset& d, const Sample& s, const Method& method, const Protocol& p,
                   const GroupIds* groups = nullptr);

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
  std::string method;  // Method::name, or "data"
  bool groups = false;
  double ade = 0.0, fde = 0.0;
  Distribution speed;     // m/s over the 12 predicted frame intervals
  Distribution nn;        // m, nearest recorded neighbour at the 12 predicted frames
  double overlaps = 0.0;  // share of the predicted frames with a recorded person within overlap_distance
};

struct SampleResult {
  int id = 0;
  std::int64_t first_frame = 0;
  std::vector<double> ade, fde;  // one per method
};

struct DatasetResult {
  std::string name, path, split = "all";
  double frame_interval = 0.4;
  std::size_t samples = 0;
  std::vector<SampleResult> per_sample;
  MethodResult data;                  // the record's own speed, nn and overlap statistics
  std::vector<MethodResult> methods;  // in the order of the methods evaluated
  double seconds = 0.0;               // wall clock of the evaluation
};

// Every method on every sample of `d` (on the pool's threads when given; the same numbers, bit for
// bit, with any pool or none). `samples` (optional): only these, instead of every sample of d.
DatasetResult evaluate(const Dataset& d, const std::vector<Method>& methods, const Protocol& p,
                       const GroupIds* groups = nullptr, ThreadPool* threads = nullptr,
                       const std::vector<Sample>* samples = nullptr);

}  // namespace hunav::realism
