#pragma once
// A small thread pool owned by its user (hunav.VectorSimulation): run(count, work) calls work(i) for
// every i in [0, count) on the calling thread and the pool's threads, and returns when all are done.
// No Python inside: the caller releases the GIL around run().
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace hunav::python {

class WorkerPool {
 public:
  // `threads`: threads in all, the caller's included (threads - 1 are started here).
  explicit WorkerPool(int threads) {
    // The generation a thread starts from is taken here, not when the thread first runs: one that
    // starts late (a loaded machine) must still see the jobs and the stop that came before it ran.
    const std::uint64_t start = generation_.load();
    for (int t = 1; t < threads; ++t) threads_.emplace_back([this, start] { loop(start); });
  }
  ~WorkerPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
      generation_.fetch_add(1);
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(threads_.size()) + 1; }

  // work(i) must not throw (catch per item); it runs while run() waits, so it may refer to the
  // caller's locals. One run() at a time.
  void run(int count, const std::function<void(int)>& work) {
    if (count <= 0) return;
    if (threads_.empty() || count == 1) {
      for (int i = 0; i < count; ++i) work(i);
      return;
    }
    std::uint64_t gen = 0;
    bool sleeping = false;
    {
      // The job's fields change together, under the lock: a worker copies them together.
      std::lock_guard<std::mutex> lock(mutex_);
      gen = generation_.load() + 1;
      work_ = &work;
      count_ = count;
      done_.store(0);
      ticket_.store(gen << 32);
      generation_.store(gen);
      sleeping = sleepers_ > 0;
    }
    if (sleeping) wake_.notify_all();
    take(gen, work, count);
    // The items the workers took: usually done by now, or nearly (they are the same size).
    for (int spin = 0; done_.load(std::memory_order_acquire) < count; ++spin) {
      if (spin < kCallerSpins) {
        std::this_thread::yield();
        continue;
      }
      std::unique_lock<std::mutex> lock(mutex_);
      caller_waiting_ = true;
      finished_.wait(lock, [&] { return done_.load() >= count; });
      caller_waiting_ = false;
      break;
    }
  }

 private:
  // Yields of the caller before it sleeps, and how long a worker keeps looking for the next job
  // before it sleeps: a wake-up through the kernel costs tens of microseconds in a virtual machine,
  // about what a Python step takes between two calls of run().
  static constexpr int kCallerSpins = 200;
  static constexpr std::chrono::microseconds kWorkerSpin{200};

  // Claims items of generation `gen` until none is left. A worker late for a job finds its items
  // taken (or a later job's ticket, which it cannot claim): the job's `work` is called only while
  // run() waits for it.
  void take(std::uint64_t gen, const std::function<void(int)>& work, int count) {
    for (;;) {
      std::uint64_t t = ticket_.load();
      std::uint64_t index = 0;
      do {
        index = t & 0xffffffffu;
        if ((t >> 32) != (gen & 0xffffffffu) || index >= static_cast<std::uint64_t>(count)) return;
      } while (!ticket_.compare_exchange_weak(t, t + 1));
      work(static_cast<int>(index));
      if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == count) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (caller_waiting_) finished_.notify_one();
      }
    }
  }

  void loop(std::uint64_t seen) {
    for (;;) {
      const auto until = std::chrono::steady_clock::now() + kWorkerSpin;
      for (int spin = 0; generation_.load() == seen; ++spin) {
        if ((spin & 63) == 63 && std::chrono::steady_clock::now() > until) break;
        std::this_thread::yield();
      }
      const std::function<void(int)>* work = nullptr;
      int count = 0;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ++sleepers_;
        wake_.wait(lock, [&] { return stop_ || generation_.load() != seen; });
        --sleepers_;
        if (stop_) return;
        seen = generation_.load();
        work = work_;
        count = count_;
      }
      take(seen, *work, count);
    }
  }

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_, finished_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<std::uint64_t> ticket_{0};  // generation (high 32 bits) and the next item (low 32 bits)
  std::atomic<int> done_{0};
  // Under mutex_:
  int sleepers_ = 0;
  bool stop_ = false;
  bool caller_waiting_ = false;
  const std::function<void(int)>* work_ = nullptr;
  int count_ = 0;
};

}  // namespace hunav::python
