#pragma once
// One sample as the metrics see it, and the per-person quantities several metrics share.
//
// The evaluator streams: every metric sees each sample once, in time order, through a SampleView,
// and keeps only what it needs of the past (metrics.hpp). A view shows the robot and either every
// person of the sample or the people of one behavior (the per-behavior files); the expensive
// per-person quantities (social and obstacle forces, the v2 costs, distances) are computed on first
// use and cached in a SampleCache for the whole sample, so every metric and every view reuses them.
// Each cached value is computed by exactly the expression a metric would use, so caching never
// changes a result.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hunav/evaluator/result_files.hpp"

namespace hunav::evaluator {

// The per-person quantities of one sample, filled on first use. Owned by whoever feeds the samples;
// reset() before each sample.
class SampleCache {
 public:
  void reset(std::size_t people) {
    people_.resize(people);
    for (auto& p : people_) p.have = 0;
    have_robot_obstacle_ = false;
  }

 private:
  friend class SampleView;
  struct Person {
    std::uint32_t have = 0;                // bit set of the fields below that are filled
    double surface = 0.0;                  // surface distance to the robot
    Vec2 social_on_person = Vec2::Zero();  // F_soc(robot -> person), the simulator's model
    Vec2 social_on_robot = Vec2::Zero();   // F_soc(person -> robot)
    Vec2 v1_on_person = Vec2::Zero();      // the same with HuNavSim v1's force (metrics_v1)
    Vec2 v1_on_robot = Vec2::Zero();
    Vec2 obstacle = Vec2::Zero();  // sum over the person's obstacle points
    Vec2 ahead = Vec2::Zero();     // the point 1.5 m ahead (group o-space proxy)
    double fear = 0.0;
    double panic = 0.0;
    double theta = 0.0;  // visibility of the robot to the person
    double distance = 0.0;
    bool visible = false;
  };
  std::vector<Person> people_;
  bool have_robot_obstacle_ = false;
  Vec2 robot_obstacle_ = Vec2::Zero();
};

class SampleView {
 public:
  // Every person of sample `s` of `r`. `cache` holds this sample's shared quantities (reset for it).
  SampleView(const Recording& r, const Sample& s, SampleCache& cache)
      : recording_(&r), sample_(&s), all_(r.agents(s).begin()), size_(s.agents_count), cache_(&cache) {}
  // The people at the positions `members` of the sample (ascending), in that order.
  SampleView(const Recording& r, const Sample& s, SampleCache& cache, const std::vector<std::uint32_t>& members)
      : recording_(&r),
        sample_(&s),
        all_(r.agents(s).begin()),
        members_(members.data()),
        subset_(true),
        size_(members.size()),
        cache_(&cache) {}

  double t() const { return sample_->t; }
  const EntityState& robot() const { return sample_->robot; }
  // People in the view.
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const EntityState& agent(std::size_t j) const { return all_[index(j)]; }
  Slice<Vec2> obstacles(const EntityState& e) const { return recording_->obstacles(e); }

  // Shared per-person quantities (person j of the view), computed once per sample:
  // surface distance |p - q_j| - r - r_j (negative when the discs overlap);
  double surfaceDistance(std::size_t j) const;
  // F_soc(robot -> j) and F_soc(j -> robot) of the simulator's model (omega_s = 5);
  const Vec2& socialForceOnPerson(std::size_t j) const;
  const Vec2& socialForceOnRobot(std::size_t j) const;
  // the same with HuNavSim v1's evaluator force (metrics_v1::socialForceV1);
  const Vec2& v1ForceOnPerson(std::size_t j) const;
  const Vec2& v1ForceOnRobot(std::size_t j) const;
  // the obstacle force of the person's / the robot's obstacle points, summed over the points;
  const Vec2& obstacleForceSum(std::size_t j) const;
  const Vec2& robotObstacleForceSum() const;
  // (x + 1.5 cos yaw, y + 1.5 sin yaw) of person j;
  const Vec2& aheadPoint(std::size_t j) const;
  // the v2 danger costs (dangerFearAt, dangerPanicAt);
  double fear(std::size_t j) const;
  double panic(std::size_t j) const;
  // whether the robot is in person j's field of view, with the angle and the centre distance.
  bool visible(std::size_t j, double& theta, double& distance) const;

  // Quantities of the view, computed once per view:
  // the person with the smallest surface distance (first on ties); false without people;
  bool closestPerson(std::size_t& j) const;
  // m = max(0, smallest surface distance); the view must have people;
  double closestPersonDistance() const;
  // g = min over the groups of the view of max(0, |p - c| - r), c = mean of the members' ahead
  // points; false when no person of the view is in a group.
  bool closestGroupDistance(double& g) const;

 private:
  std::size_t index(std::size_t j) const { return subset_ ? members_[j] : j; }
  SampleCache::Person& person(std::size_t j) const { return cache_->people_[index(j)]; }

  const Recording* recording_;
  const Sample* sample_;
  const EntityState* all_;
  const std::uint32_t* members_ = nullptr;
  bool subset_ = false;
  std::size_t size_;
  SampleCache* cache_;
  // Per view.
  mutable bool have_closest_ = false;
  mutable std::size_t closest_ = 0;
  mutable bool have_group_ = false;
  mutable bool group_present_ = false;
  mutable double group_distance_ = 0.0;
};

}  // namespace hunav::evaluator
