#pragma once
// `scl`: the dwb local planner on a costmap with a social layer (in the spirit of ROS
// social_navigation_layers and nav2_social_costmap_plugin). Around every detected person it adds an
// asymmetric Gaussian cost: wider in front of the person than behind and to the sides, and
// stretched along the person's velocity the faster they walk. The cost stays below lethal, so it
// only steers: A* plans around it (global_planner.cost_weight) and the obstacle critic
// (dwb.obstacle_weight) prefers rollouts through cheaper cells, so the robot keeps more distance.
#include "dwb_planner.hpp"

namespace hunav::planners {

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
  std::vector<double> column_x_;        // scratch: the x of the costmap's column centres
  std::vector<double> row_exponent_;    // scratch: the exponents of a row's cells
};

}  // namespace hunav::planners
