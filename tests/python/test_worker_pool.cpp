// hunav.VectorSimulation's thread pool (python/src/worker_pool.hpp): every item of every run() is
// done exactly once, and a pool is destroyed however late its threads start.
#include <gtest/gtest.h>

#include <atomic>
#include <vector>

#include "worker_pool.hpp"

using hunav::python::WorkerPool;

// A pool destroyed before its threads first ran used to hang: a thread that started after the
// destructor's stop took the stopped generation for the one it had seen and slept forever
// (python_test_vector timed out now and then on a loaded machine; this loop hung within the first
// thousand pools every time).
TEST(WorkerPool, IsDestroyedEvenBeforeItsThreadsStart) {
  for (int i = 0; i < 2000; ++i) {
    WorkerPool pool(3);
    EXPECT_EQ(pool.threads(), 3);
  }
}

TEST(WorkerPool, ThreadsThatStartAfterSomeJobsStillTakeTheNextOnes) {
  for (int i = 0; i < 500; ++i) {
    WorkerPool pool(3);
    std::atomic<int> sum{0};
    for (int job = 0; job < 4; ++job) pool.run(5, [&](int k) { sum += k + 1; });
    EXPECT_EQ(sum.load(), 4 * (1 + 2 + 3 + 4 + 5));  // 4 jobs of items 1..5: 60
  }
}

TEST(WorkerPool, EveryItemIsDoneOnceInEveryRun) {
  WorkerPool pool(3);
  for (int count : {1, 2, 3, 7, 64, 1000}) {
    for (int repeat = 0; repeat < 50; ++repeat) {
      std::vector<std::atomic<int>> done(static_cast<std::size_t>(count));
      pool.run(count, [&](int k) { done[static_cast<std::size_t>(k)].fetch_add(1); });
      for (int k = 0; k < count; ++k) ASSERT_EQ(done[static_cast<std::size_t>(k)].load(), 1) << count << " " << k;
    }
  }
}

TEST(WorkerPool, OneThreadRunsEverythingOnTheCaller) {
  WorkerPool pool(1);
  std::vector<int> order;
  pool.run(4, [&](int k) { order.push_back(k); });  // no other thread: no race on the vector
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3}));
}
