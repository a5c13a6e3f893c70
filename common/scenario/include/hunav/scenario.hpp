#pragma once
// A scenario: static map, robot, people (HuNavSim agents layout), clock. Defined once, in YAML, and
// shared by runs, tests and benchmarks. scenarios/README.md documents every key.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hunav/bounds.hpp"  // the bounds the loader enforces (kMaxCoordinate, ...)
#include "hunav/geometry.hpp"
#include "hunav/motion_model.hpp"

namespace hunav {

// HuNavSim behavior codes.
enum class Behavior : int { Regular = 1, Impassive = 2, Surprised = 3, Scared = 4, Curious = 5, Threatening = 6 };
const char* behaviorName(int code);

struct BehaviorParams {
  int configuration = 0;  // 0 default, 1 custom, 2 random normal, 3 random uniform
  double duration = 40.0;
  bool once = true;
  double vel = 1.0;
  double dist = 0.0;
  double goal_force_factor = 2.0;
  double obstacle_force_factor = 10.0;
  double social_force_factor = 5.0;
  double other_force_factor = 20.0;
};

struct AgentConfig {
  int id = -1;
  std::string name;
  int skin = 0;
  int behavior = 1;
  BehaviorParams params;
  std::optional<MotionModel> people_model;  // its own people model (`people_model:`); none: the scenario's
  std::string behavior_tree;                // empty = built-in tree of the behavior; else a path to open
  int behavior_tree_line = 0;               // of the behavior_tree key, for error messages (0: unknown)
  int group_id = -1;
  double max_vel = 1.0;  // m/s, desired speed
  double radius = 0.35;  // m
  Vec2 position = Vec2::Zero();
  double yaw = 0.0;
  double goal_radius = 0.0;
  bool cyclic_goals = true;
  std::vector<Vec2> goals;
  std::string source_file;  // where it was defined, for error messages
  int source_line = 0;
};

struct RobotLimits {
  double max_v = 0.6;       // m/s, forward (x of the robot frame)
  double min_v = 0.0;       // m/s (negative allows reversing)
  double max_w = 1.2;       // rad/s
  double max_acc_v = 1.0;   // m/s^2
  double max_acc_w = 2.5;   // rad/s^2
  double max_vy = 0.6;      // m/s, lateral (y of the robot frame), holonomic drive only: |vy| <= max_vy
  double max_acc_vy = 1.0;  // m/s^2, holonomic drive only
};

struct LaserConfig {
  int beams = 180;
  double fov = 2.0 * kPi;   // rad, centred on the robot heading
  double range_min = 0.05;  // m
  double range_max = 8.0;   // m
  double noise_std = 0.0;   // m, Gaussian, seeded
};

enum class RobotShape { Circle, Box };
enum class RobotDrive { Differential, Holonomic };

struct RobotConfig {
  int id = 0;
  RobotShape shape = RobotShape::Circle;
  double radius = 0.3;  // m; for a box, its half diagonal (the circle that contains it)
  double length = 0.0;  // m, box only: extent along the heading
  double width = 0.0;   // m, box only: extent across the heading
  RobotDrive drive = RobotDrive::Differential;
  Vec2 start = Vec2::Zero();
  double start_yaw = 0.0;
  bool has_goal = false;
  Vec2 goal = Vec2::Zero();
  double goal_yaw = 0.0;
  double goal_radius = 0.3;
  RobotLimits limits;
  LaserConfig laser;
  double perception_range = 8.0;      // m, people detections
  double perception_fov = 2.0 * kPi;  // rad, centred on the robot heading
  double perception_noise_std = 0.0;  // m (position) and m/s (velocity) of a detection, Gaussian, seeded
  double control_rate = 10.0;         // Hz of simulation time
};

// Which obstacle points feed a person's social-force obstacle term (scenarios/README.md, `people:`).
enum class ObstaclePoints {
  Closest,  // the closest point of all static geometry within obstacle_radius (HuNavSim's wrapper)
  Each,     // the closest point of every shape within obstacle_radius, forces summed (lightsfm 2025)
  Mean,     // the same points, forces averaged (lightsfm 2022)
};
const char* obstaclePointsName(ObstaclePoints p);

// How a person finds its way to a goal.
enum class PeopleNavigation {
  Path,    // a route over the static map; the next visible waypoint is the desired direction
  Direct,  // straight at the goal (HuNavSim)
};
const char* peopleNavigationName(PeopleNavigation n);

// The human model's scenario-wide settings (`people:` keys besides the agents).
struct PeopleModel {
  ObstaclePoints obstacle_points = ObstaclePoints::Closest;
  PeopleNavigation navigation = PeopleNavigation::Path;
  double route_resolution = 0.1;  // m, cell side of the people's route grid
  bool give_way = false;          // a person held still face to face steps back (manager/README.md)
  // Pairs of people whose social force is certainly below this fraction of the largest one pair
  // exerts are skipped (0: every pair within the cut-off; manager/README.md, "Crowds").
  double force_tolerance = 0.0;
  MotionModel model;  // `people.model`: how everybody walks (default HuNavSim's SFM, `sfm`)
};

// One condition of the scenario's `expect:` block (scenarios/README.md; docs/metrics.md,
// "Expectations"), checked on the final metrics when the episode ends (runner/expectations.hpp).
struct Expectation {
  enum class Kind {
    Equal,   // `name: 3` or `name: true`: the metric equals the value exactly
    Range,   // `name: {min: X, max: Y}`: min <= metric <= max, either bound optional
    Status,  // `status: goal_reached`: the episode's end status
  };
  std::string metric;  // a metric name of the evaluator (checked where the run is set up), or "status"
  Kind kind = Kind::Equal;
  bool is_bool = false;            // Equal: written as true/false (value 1/0), for boolean metrics only
  double value = 0.0;              // Equal
  std::optional<double> min, max;  // Range
  std::string status;              // Status: goal_reached, time_limit or stuck
  std::string file;                // where it was written, for file:line: key errors
  int line = 0;
};

// The grid the static map is published on (MAP; occupancy_grid.hpp): the cells of the scenario's
// first map_server map (its resolution, and its origin as a corner of the lattice) when that map is
// not turned, else `resolution`-sided cells with a corner at the world's origin.
struct MapGrid {
  double resolution = 0.05;  // m
  Vec2 anchor = Vec2::Zero();
};

struct Scenario {
  std::string name;
  std::string file;          // path it was loaded from
  double dt = 0.01;          // s
  double time_limit = 60.0;  // s of simulation time
  std::uint64_t seed = 1;
  double obstacle_radius = 3.0;  // m, static shapes closer than this feed an agent's obstacle force
  // evaluation.sample_rate: Hz of simulation time at which the evaluator records states.csv and
  // evaluates the metrics (its --sample-rate); 0 = every world state. A `--sample-rate` flag overrides it.
  double evaluation_sample_rate = 0.0;
  // evaluation.metrics: the evaluator's metrics file (its --metrics), resolved against the scenario's
  // folder; empty = every metric. A `--metrics` flag overrides it.
  std::string evaluation_metrics;
  std::vector<Shape> shapes;  // static geometry (map_server maps become rectangles here)
  MapGrid map_grid;           // how `shapes` are published as an occupancy grid (MAP)
  RobotConfig robot;
  std::vector<AgentConfig> agents;
  // HuNavSim 2's global_goals of the agents layout (id -> point; integer ids only), for the trees'
  // goal_id ports; empty when the layout has none.
  std::map<int, Vec2> global_goals;
  PeopleModel people_model;
  // The episode ends with status `stuck` when, for stuck_timeout seconds of simulation time, the
  // robot has neither left a circle of stuck_distance around where it last made progress nor come
  // stuck_distance closer to its goal than ever before. 0 = never. A scenario file without the key
  // gets defaultStuckTimeout(robot).
  double stuck_timeout = 0.0;             // s
  double stuck_distance = 0.5;            // m
  std::vector<Expectation> expectations;  // `expect:`, in file order (empty: none)

  // Bounds of everything in the scenario, with a margin.
  void bounds(Vec2& lo, Vec2& hi, double margin = 1.0) const;
};

// The stuck_timeout of a scenario file that sets none: kDefaultStuckFactor times the straight-line
// time from the robot's start to its goal at its top speed (robot.limits.max_v), and at least
// kMinDefaultStuckTimeout; 0 (never) without a goal.
inline constexpr double kDefaultStuckFactor = 2.0;
inline constexpr double kMinDefaultStuckTimeout = 60.0;  // s
double defaultStuckTimeout(const RobotConfig& robot);

// A --duration override, checked like the file's time_limit; throws ConfigError("--duration: ...").
void checkDurationOverride(double duration);

// How an agent's behavior_tree travels in agent_state_t: relative to the scenario file's folder, so
// that the run's fingerprint (which hashes the messages) does not depend on the working directory or
// on how the scenario's path was written. Empty scenario_file: the path as it is.
std::string behaviorTreeReference(const std::string& scenario_file, const std::string& tree_path);
// The file a reference names: resolved against the scenario file's folder (absolute references as
// they are; without a scenario, relative to the working directory).
std::string resolveBehaviorTree(const std::string& scenario_file, const std::string& reference);

// Loads and validates a scenario file. Throws ConfigError("file:line: key: what").
// `seed_override` >= 0 replaces the file's seed (it drives the random agent parameters too).
Scenario loadScenario(const std::string& path, long long seed_override = -1);

// Where a map_server map's cells lie: their side, and the pose of the picture's lower-left corner.
struct OccupancyMapFrame {
  double resolution = 0.0;  // m
  Vec2 origin = Vec2::Zero();
  double yaw = 0.0;  // rad
};
// Every person walks with this people model (a preset name, or a parameter file relative to the
// working directory), whatever the scenario and its agents say: --people-model of hunav_run,
// hunav_manager and the scripts. Throws ConfigError naming "--people-model".
void overridePeopleModel(Scenario& s, const std::string& name_or_file);
// The people model a run records (run.json, metrics.csv, the summary): its name (or file) when every
// person walks with the same one, else "mixed:" and the names joined by '+' (in name order).
std::string peopleModelLabel(const Scenario& s);

// Reads a ROS map_server map (`.yaml` with image, resolution, origin, negate, occupied_thresh,
// free_thresh, mode + a PGM image, P5 or P2, relative to the yaml) and returns its occupied cells merged
// into rectangles (closed polygons, counter-clockwise from the lower left corner), and, when `frame`
// is given, where its cells lie. Throws ConfigError.
std::vector<Shape> loadOccupancyMap(const std::string& yaml_path, OccupancyMapFrame* frame = nullptr);

// Loads a HuNavSim agents file (v1 integer behavior or v1.5 behavior mapping).
// `seed` drives the random configuration modes (with each agent's id).
// `global_goals` (optional) receives HuNavSim 2's global_goals with integer ids.
std::vector<AgentConfig> loadAgentsFile(const std::string& path, std::uint64_t seed,
                                        std::map<int, Vec2>* global_goals = nullptr);

}  // namespace hunav
