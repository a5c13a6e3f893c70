#include "hunav/thread_pool.hpp"

#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace hunav {

// A lane: one thread, one long job at a time.
struct ThreadPool::LongJob::Lane {
  std::mutex mutex;
  std::condition_variable changed;
  std::function<void()> job;
  bool taken = false;    // a LongJob holds it
  bool running = false;  // job set and not returned yet
  bool stop = false;
  std::thread thread;

  void loop() {
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      changed.wait(lock, [this] { return stop || running; });
      if (stop) return;
      std::function<void()> current = std::move(job);
      lock.unlock();
      current();  // must not throw (startLongJob)
      lock.lock();
      running = false;
      changed.notify_all();
    }
  }
};

struct ThreadPool::Impl {
  std::chrono::microseconds spin{0};
  std::vector<std::thread> helpers;
  std::vector<std::unique_ptr<LongJob::Lane>> lanes;

  std::mutex user;  // held by the run() that has the helpers
  std::mutex mutex;
  std::condition_variable wake, finished;
  std::atomic<std::uint64_t> generation{0};
  std::atomic<std::uint64_t> ticket{0};  // generation (high 32 bits) and the next item (low 32 bits)
  std::atomic<int> done{0};
  std::atomic<bool> failed{false};
  // Under mutex:
  int sleepers = 0;
  bool stop = false;
  bool caller_waiting = false;
  const std::function<void(int, int)>* work = nullptr;
  int count = 0;
  std::exception_ptr error;

  // Claims items of generation `gen` until none is left. A helper late for a job finds its items
  // taken (or a later job's ticket, which it cannot claim): `work` runs only while run() waits.
  void take(std::uint64_t gen, const std::function<void(int, int)>& job, int items, int slot) {
    for (;;) {
      std::uint64_t t = ticket.load();
      std::uint64_t index = 0;
      do {
        index = t & 0xffffffffu;
        if ((t >> 32) != (gen & 0xffffffffu) || index >= static_cast<std::uint64_t>(items)) return;
      } while (!ticket.compare_exchange_weak(t, t + 1));
      runItem(job, static_cast<int>(index), slot, items);
    }
  }

  void runItem(const std::function<void(int, int)>& job, int index, int slot, int items) {
    if (!failed.load(std::memory_order_relaxed)) {
      try {
        job(index, slot);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        failed.store(true);
      }
    }
    if (done.fetch_add(1, std::memory_order_acq_rel) + 1 == items) {
      std::lock_guard<std::mutex> lock(mutex);
      if (caller_waiting) finished.notify_one();
    }
  }

  void helperLoop(int slot, std::uint64_t seen) {
    for (;;) {
      if (spin.count() > 0) {
        const auto until = std::chrono::steady_clock::now() + spin;
        for (int n = 0; generation.load() == seen; ++n) {
          if ((n & 63) == 63 && std::chrono::steady_clock::now() > until) break;
          std::this_thread::yield();
        }
      }
      const std::function<void(int, int)>* job = nullptr;
      int items = 0;
      {
        std::unique_lock<std::mutex> lock(mutex);
        ++sleepers;
        wake.wait(lock, [&] { return stop || generation.load() != seen; });
        --sleepers;
        if (stop) return;
        seen = generation.load();
        job = work;
        items = count;
      }
      take(seen, *job, items, slot);
    }
  }
};

ThreadPool::Size ThreadPool::forThisMachine(int lanes) {
  Size size;
  size.helpers = std::thread::hardware_concurrency() > 1 ? 1 : 0;
  size.lanes = lanes;
  return size;
}

ThreadPool::ThreadPool(const Size& size) : impl_(std::make_unique<Impl>()) {
  impl_->spin = size.spin;
  // The threads inherit the creator's signal mask: all blocked while they are made.
  sigset_t all;
  sigset_t previous;
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &previous);
  // A helper's first generation is taken here, not when it first runs: one that starts late (a
  // loaded machine) must still see the jobs and the stop that came before it ran.
  const std::uint64_t start = impl_->generation.load();
  // Named for top -H, perf and gdb.
  for (int slot = 1; slot <= size.helpers; ++slot) {
    impl_->helpers.emplace_back([impl = impl_.get(), slot, start] { impl->helperLoop(slot, start); });
    pthread_setname_np(impl_->helpers.back().native_handle(), ("hunav-helper" + std::to_string(slot)).c_str());
  }
  for (int k = 0; k < size.lanes; ++k) {
    impl_->lanes.push_back(std::make_unique<LongJob::Lane>());
    LongJob::Lane* lane = impl_->lanes.back().get();
    lane->thread = std::thread([lane] { lane->loop(); });
    pthread_setname_np(lane->thread.native_handle(), ("hunav-lane" + std::to_string(k + 1)).c_str());
  }
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stop = true;
    impl_->generation.fetch_add(1);
  }
  impl_->wake.notify_all();
  for (std::thread& t : impl_->helpers) t.join();
  for (auto& lane : impl_->lanes) {
    {
      std::lock_guard<std::mutex> lock(lane->mutex);
      lane->stop = true;
    }
    lane->changed.notify_all();
    lane->thread.join();
  }
}

int ThreadPool::slots() const { return static_cast<int>(impl_->helpers.size()) + 1; }
int ThreadPool::lanes() const { return static_cast<int>(impl_->lanes.size()); }

void ThreadPool::run(int count, const std::function<void(int, int)>& work) {
  if (count <= 0) return;
  std::unique_lock<std::mutex> have_helpers(impl_->user, std::try_to_lock);
  if (impl_->helpers.empty() || count == 1 || !have_helpers.owns_lock()) {
    for (int i = 0; i < count; ++i) work(i, 0);
    return;
  }
  Impl& p = *impl_;
  std::uint64_t gen = 0;
  bool sleeping = false;
  {
    // The job's fields change together, under the lock: a helper copies them together.
    std::lock_guard<std::mutex> lock(p.mutex);
    gen = p.generation.load() + 1;
    p.work = &work;
    p.count = count;
    p.error = nullptr;
    p.failed.store(false);
    p.done.store(0);
    p.ticket.store((gen << 32) | 1);  // item 0 is the caller's
    p.generation.store(gen);
    sleeping = p.sleepers > 0;
  }
  if (sleeping) p.wake.notify_all();
  p.runItem(work, 0, 0, count);
  p.take(gen, work, count, 0);
  // The items the helpers took: often done by now, or nearly.
  constexpr int kCallerSpins = 200;
  const int spins = p.spin.count() > 0 ? kCallerSpins : 0;
  for (int n = 0; p.done.load(std::memory_order_acquire) < count; ++n) {
    if (n < spins) {
      std::this_thread::yield();
      continue;
    }
    std::unique_lock<std::mutex> lock(p.mutex);
    p.caller_waiting = true;
    p.finished.wait(lock, [&] { return p.done.load() >= count; });
    p.caller_waiting = false;
    break;
  }
  std::exception_ptr error;
  {
    std::lock_guard<std::mutex> lock(p.mutex);
    error = std::exchange(p.error, nullptr);
  }
  if (error) std::rethrow_exception(error);
}

ThreadPool::LongJob::~LongJob() {
  std::unique_lock<std::mutex> lock(lane_.mutex);
  lane_.changed.wait(lock, [this] { return !lane_.running; });
  lane_.taken = false;  // free for the next startLongJob
}

std::unique_ptr<ThreadPool::LongJob> ThreadPool::startLongJob(std::function<void()> job) {
  for (auto& lane : impl_->lanes) {
    std::lock_guard<std::mutex> lock(lane->mutex);
    if (lane->taken) continue;
    lane->taken = true;
    lane->job = std::move(job);
    lane->running = true;
    lane->changed.notify_all();
    return std::unique_ptr<LongJob>(new LongJob(*lane));
  }
  return nullptr;
}

}  // namespace hunav
