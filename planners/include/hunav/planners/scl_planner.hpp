#pragma once
// `scl`: the dwb local planner on a costmap with a social layer (in the spirit of ROS
// social_navigation_layers and nav2_social_costmap_plugin). Around every detected person it adds an
// asymmetric Gaussian cost: wider in front of the person than behind and to the sides, and
// stretched along the person's velocity the faster they walk. The cost stays below lethal, so it
// only steers: A* plans around it (global_planner.cost_weight) and the obstacle critic
// (dwb.obstacle_weight) prefers rollouts through cheaper cells, so the robot keeps more distance.
#include "hunav/planners/dwb_planner.hpp"

namespace hunav::planners {

// scl's defaults for keys of other sections (config/scl.yaml): dwb.evade_people is true and
constexpr double kSclCostWeight = 6.0;       // global_planner.cost_weight (dwb: 3)
constexpr double kSclHeuristicWeight = 1.5;  // global_planner.heuristic_weight (dwb: 1)

// Section `scl:` of --config (planners/config/scl.yaml lists every key with its default).
struct SclParams {
  double amplitude = 252.0;    // cost (0..252) at the person's surface
  double sigma_front = 1.0;    // m, Gaussian spread in front of a standing person
  double sigma_rear = 0.5;     // m, spread behind
  double sigma_side = 0.8;     // m, spread to either side
  double speed_factor = 1.0;   // s: the front spread grows by speed * speed_factor (m/s * s = m)
  double cutoff = 10.0;        // cost below which cells are left alone (bounds the marked area)
  double moving_speed = 0.05;  // m/s below which the person's yaw (not its velocity) gives the front

  void readSection(const YamlReader* config);
};

// The social cost (0..amplitude) at `p` of a person at `center` with `radius`, heading `heading`
// (unit vector) at `speed`. Exposed for tests.
double socialCost(const SclParams& params, const Vec2& center, double radius, const Vec2& heading, double speed,
                  const Vec2& p);

class SclPlanner : public DwbPlanner {
 public:
  SclPlanner(const Scenario& scenario, const DwbParams& dwb, const SclParams& scl = {});
  const SclParams& sclParams() const { return scl_; }

  // Reads sections costmap, global_planner, dwb, recovery and scl.
  static std::unique_ptr<Planner> create(const Scenario& scenario, const YamlReader* config);

 protected:
  void updateLayers(const robot_observation_t& obs, Costmap& costmap) override;

 private:
  // floor(amplitude * exp(-e)) (at most `top`), from the thresholds.
  std::uint8_t exponentCost(double e, int top) const;

  SclParams scl_;
  double max_exponent_ = 0.0;  // log(amplitude / cutoff): beyond it the cost is below the cutoff
  double bins_per_exponent_ = 0.0;
  std::vector<double> cost_threshold_;  // [c]: the largest exponent whose cost is still >= c
  std::vector<std::uint8_t> bin_cost_;  // the cost at the start of each bin of exponents
};

}  // namespace hunav::planners
