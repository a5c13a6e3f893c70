#pragma once
// The social force between people in cut-off mode (people_social.cpp): the neighbour grid, the
// batched pair kernel and its scalar reference.
// Internal to the manager; tests include it to check the kernel against its reference.
#include <cmath>
#include <cstddef>
#include <memory>
#include <vector>

#include "hunav/manager/tick_context.hpp"
#include "hunav/thread_pool.hpp"

namespace hunav::manager {

// Uniform grid over the snapshot's people, cells of `cell` metres; agents of a cell sorted by id, so
// a query visits neighbours in an order that does not depend on the request order. Rebuilding it
// reuses its storage (no allocation once it has seen the largest crowd).
class NeighborGrid {
 public:
  void build(const std::vector<SfmBody>& bodies, const std::vector<int>& order, double cell);
  // Calls f(j) for every body within `radius` (<= cell) of p, in a fixed order.
  template <class F>
  void forEachNear(const Vec2& p, double radius, F&& f) const;
  // The side of a cell (m): forEachNear reaches this far.
  double cell() const { return cell_; }
  // Calls f(i, j) once for every unordered pair within `radius` (<= cell), in a fixed order: by
  // cell, then for each body of the cell the rest of its own cell and the forward half of the 3x3
  // neighbourhood, (+1,0), (-1,+1), (0,+1), (+1,+1).
  template <class F>
  void forEachPair(double radius, F&& f) const;

 private:
  friend class PeopleSocialForces;

  double cell_ = 1.0;
  Vec2 origin_ = Vec2::Zero();
  int nx_ = 0, ny_ = 0;
  std::vector<int> start_;  // nx*ny+1 offsets into items_
  std::vector<int> items_;  // body indices, cell by cell
  std::vector<int> fill_;   // build scratch
  // The bodies in items_ order, structure of arrays (the pair kernel streams through them).
  std::vector<double> x_, y_, vx_, vy_;
  const std::vector<SfmBody>* bodies_ = nullptr;
};

// The social force of section 1.5 of `other` on `me` without the weight omega_s: the formula of
// hunav::socialForceFrom with atan2 and exp replaced by polynomials (errors < 1e-10 rad and 1e-15
// relative) and theta taken from D = lambda (v_me - v_other) + e directly, so that equal
// velocities give exactly theta = 0 (no sideways force). The force of `me` on `other` is exactly
// the opposite, so the cut-off mode evaluates each pair once. This scalar form gives the same bits
// as the batched kernel of computePeopleSocial.
Vec2 unweightedSocialForce(const SfmBody& me, const SfmBody& other, const SfmParams& p);

// Fills snap.people_social from the pairs of `grid` (built on snap.agents) within `cutoff`: the
// same sums, in the same order, as forEachPair with unweightedSocialForce (people_social[i] += u,
// people_social[j] -= u), computed in batches (SIMD where the CPU has it). Keeps its storage from
// step to step (one per manager). With `threads` and a crowd worth it (crowdWorthSharing), the
// cells are shared out in chunks over the pool's slots: the same sums in the same order, the same
// bits. With `tolerance` > 0 (people.force_tolerance) the pairs whose force is certainly below
// tolerance x sqrt(2) (the largest force of one pair, exp(-d/B) <= 1) are skipped, judged from d
// and |D| before any exp or atan2; the others give the same bits, in the same order.
class PeopleSocialForces {
 public:
  PeopleSocialForces();
  ~PeopleSocialForces();
  void compute(StepSnapshot& snap, const NeighborGrid& grid, double cutoff, ThreadPool* threads = nullptr,
               double tolerance = 0.0);

 private:
  struct Workspace;
  std::unique_ptr<Workspace> ws_;
};
// One compute() with storage of its own (tests).
void computePeopleSocial(StepSnapshot& snap, const NeighborGrid& grid, double cutoff, ThreadPool* threads = nullptr,
                         double tolerance = 0.0);

// Whether handing work of `people` people to the pool's helpers pays (fewer: one thread is faster).
bool crowdWorthSharing(const ThreadPool* threads, std::size_t people);

template <class F>
void NeighborGrid::forEachNear(const Vec2& p, double radius, F&& f) const {
  if (nx_ == 0) return;
  const int cx = static_cast<int>(std::floor((p.x() - origin_.x()) / cell_));
  const int cy = static_cast<int>(std::floor((p.y() - origin_.y()) / cell_));
  const double r2 = radius * radius;
  for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, ny_ - 1); ++y)
    for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, nx_ - 1); ++x) {
      const int c = y * nx_ + x;
      for (int k = start_[c]; k < start_[c + 1]; ++k) {
        const int j = items_[k];
        if (((*bodies_)[j].position - p).squaredNorm() <= r2) f(j);
      }
    }
}

template <class F>
void NeighborGrid::forEachPair(double radius, F&& f) const {
  const double r2 = radius * radius;
  const auto& b = *bodies_;
  for (int cy = 0; cy < ny_; ++cy)
    for (int cx = 0; cx < nx_; ++cx) {
      const int c = cy * nx_ + cx;
      for (int k = start_[c]; k < start_[c + 1]; ++k) {
        const int i = items_[k];
        const Vec2& pi = b[i].position;
        for (int m = k + 1; m < start_[c + 1]; ++m)
          if ((b[items_[m]].position - pi).squaredNorm() <= r2) f(i, items_[m]);
        // forward half of the 3x3 neighbourhood: (+1,0), (-1,+1), (0,+1), (+1,+1)
        static constexpr int kOff[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
        for (const auto& o : kOff) {
          const int x = cx + o[0], y = cy + o[1];
          if (x < 0 || x >= nx_ || y >= ny_) continue;
          const int c2 = y * nx_ + x;
          for (int m = start_[c2]; m < start_[c2 + 1]; ++m)
            if ((b[items_[m]].position - pi).squaredNorm() <= r2) f(i, items_[m]);
        }
      }
    }
}

}  // namespace hunav::manager
