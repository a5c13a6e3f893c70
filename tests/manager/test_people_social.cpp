// The cut-off mode's social force between people: the batched (SIMD) kernel against its scalar
// form and against hunav::socialForceFrom.
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "hunav/manager/agent_manager.hpp"
#include "lcg.hpp"
#include "people_social.hpp"  // internal: the grid and the pair kernel

using namespace hunav;
using namespace hunav::manager;

namespace {

std::vector<SfmBody> randomCrowd(int n, double side, std::uint64_t seed) {
  Lcg u{seed};
  std::vector<SfmBody> bodies;
  for (int i = 0; i < n; ++i) {
    const double h = 2 * kPi * u(), s = 1.5 * u();
    bodies.push_back(SfmBody{i + 1, -1, Vec2(side * u(), side * u()), Vec2(s * std::cos(h), s * std::sin(h)), 0.35});
  }
  // The corner cases: two coincident people, and two walking side by side at the same velocity.
  bodies[1].position = bodies[0].position;
  bodies[3].position = bodies[2].position + Vec2(0.7, 0.4);
  bodies[3].velocity = bodies[2].velocity;
  return bodies;
}

}  // namespace

TEST(PeopleSocial, BatchedKernelGivesTheScalarFormBitForBit) {
  // computePeopleSocial (batches, AVX-512/AVX2/SSE2) against forEachPair + unweightedSocialForce:
  // the same pairs, the same values, summed in the same order, so every bit is equal.
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    StepSnapshot snap;
    snap.agents = randomCrowd(700, 30.0, seed);
    snap.index();
    NeighborGrid grid;
    grid.build(snap.agents, snap.by_id, kDefaultSocialCutoff);
    computePeopleSocial(snap, grid, kDefaultSocialCutoff);

    const SfmParams p;
    std::vector<Vec2> expected(snap.agents.size(), Vec2::Zero());
    long pairs = 0;
    grid.forEachPair(kDefaultSocialCutoff, [&](int i, int j) {
      const Vec2 u = unweightedSocialForce(snap.agents[i], snap.agents[j], p);
      expected[i] += u;
      expected[j] -= u;
      ++pairs;
    });
    EXPECT_GT(pairs, 30000);  // 700 people in 30 x 30 m: many batches
    ASSERT_EQ(snap.people_social.size(), snap.agents.size());
    for (std::size_t i = 0; i < snap.agents.size(); ++i) {
      EXPECT_EQ(snap.people_social[i].x(), expected[i].x()) << i;
      EXPECT_EQ(snap.people_social[i].y(), expected[i].y()) << i;
    }
  }
}

TEST(PeopleSocial, AnyPoolAndAnyCallersGetTheBitsOfOneThread) {
  // From 256 people the cells are shared out in chunks over a pool's slots; pools of 1, 2 and 4
  // threads, and three callers sharing one pool (whoever finds its helpers busy computes alone),
  // all get the bits of one thread without a pool, whatever the timing.
  StepSnapshot reference;
  reference.agents = randomCrowd(1000, 40.0, 9);
  reference.index();
  NeighborGrid reference_grid;
  reference_grid.build(reference.agents, reference.by_id, kDefaultSocialCutoff);
  computePeopleSocial(reference, reference_grid, kDefaultSocialCutoff);
  auto mismatches = [&](ThreadPool* threads, int rounds) {
    StepSnapshot snap;
    snap.agents = reference.agents;
    snap.index();
    NeighborGrid grid;
    grid.build(snap.agents, snap.by_id, kDefaultSocialCutoff);
    PeopleSocialForces forces;
    int wrong = 0;
    for (int r = 0; r < rounds; ++r) {
      forces.compute(snap, grid, kDefaultSocialCutoff, threads);
      for (std::size_t i = 0; i < snap.agents.size(); ++i)
        wrong += snap.people_social[i] != reference.people_social[i] ? 1 : 0;
    }
    return wrong;
  };
  for (int helpers : {0, 1, 3}) {
    ThreadPool pool(ThreadPool::Size{helpers, 0, {}});
    EXPECT_EQ(mismatches(&pool, 10), 0) << helpers << " helpers";
  }

  ThreadPool shared(ThreadPool::Size{1, 0, {}});
  constexpr int kThreads = 3, kRounds = 20;
  std::vector<int> wrong(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) threads.emplace_back([&, t] { wrong[t] = mismatches(&shared, kRounds); });
  for (std::thread& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(wrong[t], 0) << "thread " << t;
}

TEST(PeopleSocial, PolynomialFormFollowsSocialForceFrom) {
  const SfmParams p;  // omega_s = 5, lambda 2, gamma 0.35, n 2, n' 3
  // By hand: me at rest at the origin, the other at rest at (2, 0): e = D = t = (1, 0), theta = 0,
  // B = 0.35, so u = -exp(-2/0.35) (1, 0) = (-0.0032985057559390914, 0).
  const SfmBody me{1, -1, Vec2(0, 0), Vec2(0, 0), 0.35};
  const Vec2 u = unweightedSocialForce(me, SfmBody{2, -1, Vec2(2, 0), Vec2(0, 0), 0.35}, p);
  EXPECT_NEAR(u.x(), -std::exp(-2.0 / 0.35), 1e-17);
  EXPECT_EQ(u.y(), 0.0);
  // Coincident bodies: no direction, no force.
  EXPECT_EQ(unweightedSocialForce(me, me, p), Vec2::Zero());
  // Equal velocities: D = e exactly, theta = 0, so the force is along -e with no sideways part
  // (a theta of +-1e-17 from rounding would add a full sideways push of the same size).
  const SfmBody a{1, -1, Vec2(1.3, -0.4), Vec2(0.3, -0.8), 0.35};
  const SfmBody b{2, -1, Vec2(1.3 + 0.7, -0.4 + 1.4), Vec2(0.3, -0.8), 0.35};
  const Vec2 side = unweightedSocialForce(a, b, p);
  const Vec2 e = (b.position - a.position).normalized();
  EXPECT_NEAR(side.x() * e.y() - side.y() * e.x(), 0.0, 1e-16);
  EXPECT_NEAR(side.norm(), std::exp(-std::sqrt(0.7 * 0.7 + 1.4 * 1.4) / 0.35), 1e-15);
  // Random pairs: the same force as socialForceFrom / omega_s, up to the polynomial errors
  // (atan2: 1e-10 rad, which moves exp(-(n' B theta)^2) by at most ~1e-8 relative; exp: 1e-15).
  Lcg r{99};
  int compared = 0;
  for (int k = 0; k < 20000; ++k) {
    const double h1 = 2 * kPi * r(), h2 = 2 * kPi * r(), s1 = 1.5 * r(), s2 = 1.5 * r();
    const SfmBody i{1, -1, Vec2(0, 0), Vec2(s1 * std::cos(h1), s1 * std::sin(h1)), 0.35};
    const SfmBody j{2, -1, Vec2(16 * r() - 8, 16 * r() - 8), Vec2(s2 * std::cos(h2), s2 * std::sin(h2)), 0.35};
    const Vec2 fast = p.social_weight * unweightedSocialForce(i, j, p);
    const Vec2 exact = socialForceFrom(i, j, p);
    EXPECT_LE((fast - exact).norm(), 1e-8 * exact.norm() + 1e-300) << k;
    ++compared;
  }
  EXPECT_EQ(compared, 20000);
}

TEST(PeopleSocial, ATolerancePairIsSkippedExactlyWhereItsBoundSaysSo) {
  // people.force_tolerance 1e-4: a pair is skipped when d > gamma |D| ln(1/tol). Two people at rest:
  // D = e, |D| = 1, so the limit is 0.35 x ln(10^4) = 0.35 x 9.2103 = 3.2236 m. At 3.0 m the force
  // exp(-3.0/0.35) = 1.89e-4 is kept, at 3.5 m exp(-3.5/0.35) = 4.54e-5 (< 1e-4) is dropped.
  // Walking toward each other at 1 m/s each (dv = 2 m/s along e from me to the other): |D| = 2 x 2 + 1
  // = 5, the limit 5 x 3.2236 = 16.1 m, so even at 7.5 m the pair is kept (exp(-7.5/1.75) = 0.0138).
  auto pairForce = [](double d, double speed, double tolerance) {
    StepSnapshot snap;
    snap.agents = {SfmBody{1, -1, Vec2(0, 0), Vec2(speed, 0), 0.35}, SfmBody{2, -1, Vec2(d, 0), Vec2(-speed, 0), 0.35}};
    snap.index();
    NeighborGrid grid;
    grid.build(snap.agents, snap.by_id, kDefaultSocialCutoff);
    computePeopleSocial(snap, grid, kDefaultSocialCutoff, nullptr, tolerance);
    return snap.people_social[0];
  };
  EXPECT_NEAR(pairForce(3.0, 0.0, 1e-4).x(), -std::exp(-3.0 / 0.35), 1e-15);
  EXPECT_EQ(pairForce(3.0, 0.0, 1e-4), pairForce(3.0, 0.0, 0.0));
  EXPECT_NEAR(pairForce(3.5, 0.0, 0.0).x(), -4.5399929762484854e-05, 1e-16);  // exp(-10)
  EXPECT_EQ(pairForce(3.5, 0.0, 1e-4), Vec2::Zero());
  EXPECT_NE(pairForce(7.5, 1.0, 1e-4), Vec2::Zero());
  EXPECT_EQ(pairForce(7.5, 1.0, 1e-4), pairForce(7.5, 1.0, 0.0));
}

TEST(PeopleSocial, AToleranceBoundsEverySkippedPairAndKeepsTheOthersBits) {
  // On random crowds: every pair the tolerance drops has |u| <= tol x sqrt(2) (its exact force by
  // the scalar form), and each person's sum differs from the exact one by at most the sum of the
  // forces of its dropped pairs (the kept pairs are the same values added in the same order).
  for (const double tolerance : {1e-4, 1e-3}) {
    for (std::uint64_t seed : {4u, 5u}) {
      StepSnapshot snap;
      snap.agents = randomCrowd(900, 35.0, seed);
      snap.index();
      NeighborGrid grid;
      grid.build(snap.agents, snap.by_id, kDefaultSocialCutoff);
      PeopleSocialForces forces;
      ThreadPool pool(ThreadPool::Size{1, 0, {}});
      forces.compute(snap, grid, kDefaultSocialCutoff, &pool, tolerance);
      const std::vector<Vec2> approx = snap.people_social;

      const SfmParams p;
      const double limit = p.gamma * std::log(1.0 / tolerance);
      std::vector<Vec2> kept(snap.agents.size(), Vec2::Zero());
      std::vector<double> dropped(snap.agents.size(), 0.0);
      long skipped = 0, all = 0;
      grid.forEachPair(kDefaultSocialCutoff, [&](int i, int j) {
        const SfmBody &a = snap.agents[i], &b = snap.agents[j];
        const Vec2 u = unweightedSocialForce(a, b, p);
        const Vec2 d = b.position - a.position;
        const Vec2 D = p.lambda * (a.velocity - b.velocity) + d.normalized();
        ++all;
        if (d.norm() > limit * D.norm() * (1 + 1e-12)) {  // beyond the bound: dropped
          EXPECT_LE(u.norm(), tolerance * std::sqrt(2.0)) << i << " " << j;
          dropped[i] += u.norm();
          dropped[j] += u.norm();
          ++skipped;
        } else {
          kept[i] += u;
          kept[j] -= u;
        }
      });
      EXPECT_GT(skipped, all / 10) << tolerance;  // the tolerance does drop pairs
      for (std::size_t i = 0; i < snap.agents.size(); ++i) {
        // A pair right at the bound may fall either way by rounding: allow one such pair's force.
        EXPECT_LE((approx[i] - kept[i]).norm(), 2 * tolerance * std::sqrt(2.0)) << i;
      }
      // And against the exact sums: each person's error is at most the forces of its dropped pairs.
      StepSnapshot exact = snap;
      computePeopleSocial(exact, grid, kDefaultSocialCutoff);
      for (std::size_t i = 0; i < snap.agents.size(); ++i) {
        EXPECT_LE((approx[i] - exact.people_social[i]).norm(), dropped[i] + 1e-12) << i;
      }
    }
  }
}
