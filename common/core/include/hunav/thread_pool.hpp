#pragma once
// The threads a process lends to its components. The process (a main, hunav_run's series, a Python
// Simulation) creates one pool and passes it by pointer to the manager (its crowd step shares
// chunks with the helpers) and the evaluator (its per-sample writer runs on a lane). A component
// given no pool does the same work on the caller's thread, with the same results, bit for bit.
//
//   hunav::ThreadPool threads(hunav::ThreadPool::forThisMachine(1));
//   manager::ManagerNode manager(bus, &threads);
//   evaluator::EvaluatorNode evaluator(bus, options, &threads);
//
// Every thread of the pool starts with all signals blocked: SIGINT and SIGTERM reach the threads
// the process made itself, whose loops handle them (common/signals.hpp).
#include <chrono>
#include <functional>
#include <memory>

namespace hunav {

class ThreadPool {
 public:
  struct Size {
    int helpers = 0;  // threads that take run()'s items along with its caller
    int lanes = 0;    // threads lent whole to one long job each (startLongJob)
    // How long a helper keeps looking for the next run() before it sleeps, and the caller for the
    // helpers' last items: a wake-up through the kernel is dear in a virtual machine
    // (docs/performance.md, "Crowds"). 0: they sleep at once (the other threads of the process get
    // the core).
    std::chrono::microseconds spin{0};
  };
  // A simulation process's pool: one helper when the machine has a second core (the crowd step's
  // work splits in two: manager/README.md) and `lanes` lanes (1 for an evaluator's writer).
  static Size forThisMachine(int lanes);

  explicit ThreadPool(const Size& size);
  // Stops the threads; the long jobs must have ended (their LongJob handles destroyed) before.
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  // helpers + 1: the slots of run()'s work, the caller's (0) and each helper's.
  int slots() const;
  int lanes() const;

  // Calls work(item, slot) once for every item in [0, count) and returns when all are done: item 0
  // first on the calling thread (slot 0; a caller's own share of the work goes there), the others
  // on whichever thread takes them next, the caller's or a helper's (slots 1..helpers). The slot
  // says which of the caller's per-thread scratch the item may use: no two items run on one slot
  // at once.
  // After an item throws, the items not started are skipped and the first exception is rethrown.
  // While another thread's run() has the helpers (or from inside an item), every item runs on the
  // calling thread, slot 0.
  void run(int count, const std::function<void(int item, int slot)>& work);

  // A lane running one job until the job returns. Destroying the handle waits for that: the job's
  // owner asks it to return first (a stop flag and a wake-up of its own).
  class LongJob {
   public:
    ~LongJob();
    LongJob(const LongJob&) = delete;
    LongJob& operator=(const LongJob&) = delete;

   private:
    friend class ThreadPool;
    struct Lane;
    explicit LongJob(Lane& lane) : lane_(lane) {}
    Lane& lane_;
  };
  // Starts `job` on a free lane; null when every lane is taken (the caller then does the work
  // itself). The job must not throw (it would end the process, as on a std::thread of its own):
  // it hands its errors to its owner.
  std::unique_ptr<LongJob> startLongJob(std::function<void()> job);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hunav
