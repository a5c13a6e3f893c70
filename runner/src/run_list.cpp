#include "hunav/runner/run_list.hpp"

#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "hunav/config_error.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/runner/episode_list.hpp"

namespace hunav::runner {

namespace {

std::vector<std::string> splitTabs(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t from = 0;
  while (true) {
    const std::size_t tab = line.find('\t', from);
    fields.push_back(line.substr(from, tab == std::string::npos ? std::string::npos : tab - from));
    if (tab == std::string::npos) return fields;
    from = tab + 1;
  }
}

}  // namespace

std::vector<ListedRun> readRunList(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw ConfigError(file, 0, "", "cannot read the run list");
  std::vector<ListedRun> runs;
  std::set<std::string> folders;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const auto f = splitTabs(line);
    auto fail = [&](const std::string& key, const std::string& what) { throw ConfigError(file, number, key, what); };
    if (f.size() < 4 || f.size() > 6)
      fail("",
           "a run is 4 to 6 tab-separated columns: scenario file, label, planner, seed, wall-clock limit (s), "
           "planner config file (got " +
               std::to_string(f.size()) + ")");
    ListedRun run;
    run.line = number;
    run.scenario_file = f[0];
    run.label = f[1];
    run.planner = f[2];
    if (run.scenario_file.empty()) fail("scenario", "empty");
    if (!isFolderLabel(run.label))
      fail("label", "a name of letters, digits, '.', '_' or '-' (got '" + run.label + "')");
    if (run.planner != "none" && !planners::hasPlanner(run.planner))
      fail("planner", "unknown planner '" + run.planner + "'");
    const std::string& seed = f[3];
    const auto [seed_end, seed_error] = std::from_chars(seed.data(), seed.data() + seed.size(), run.seed);
    if (seed.empty() || seed_error != std::errc() || seed_end != seed.data() + seed.size() || run.seed < 0)
      fail("seed", "an integer >= 0 (got '" + seed + "')");
    if (f.size() >= 5 && !f[4].empty()) {
      const std::string& limit = f[4];
      const auto [end, error] = std::from_chars(limit.data(), limit.data() + limit.size(), run.timeout);
      if (error != std::errc() || end != limit.data() + limit.size() || !std::isfinite(run.timeout) ||
          run.timeout < 0.0)
        fail("timeout", "seconds >= 0, 0 = none (got '" + limit + "')");
    }
    if (f.size() == 6) run.planner_config = f[5];
    if (!folders.insert(batchRunFolder(run.label, run.planner, run.seed)).second)
      fail("seed", "the run " + run.label + " " + run.planner + " seed " + seed + " is listed twice");
    runs.push_back(std::move(run));
  }
  if (in.bad()) throw ConfigError(file, 0, "", "read error");
  return runs;
}

namespace {

// What the watching thread knows of a worker: its item's stop flag, cause and deadline.
struct WorkerSlot {
  std::atomic<bool> stop{false};
  std::mutex mutex;  // guards the fields below
  std::optional<std::chrono::steady_clock::time_point> deadline;
  double timeout = 0.0;
  bool busy = false;  // running an item
  bool timed_out = false;
};

}  // namespace

std::vector<int> runInParallel(std::size_t count, int jobs, const std::atomic<bool>& stop,
                               const std::function<double(std::size_t)>& timeout_of, const ListedRunFn& run) {
  std::vector<int> codes(count, -1);
  if (count == 0) return codes;
  if (jobs < 1) jobs = 1;
  if (static_cast<std::size_t>(jobs) > count) jobs = static_cast<int>(count);
  std::vector<WorkerSlot> slots(static_cast<std::size_t>(jobs));
  std::atomic<std::size_t> next{0};
  std::mutex done_mutex;
  std::condition_variable done_changed;
  int running = jobs;

  auto work = [&](int worker) {
    WorkerSlot& slot = slots[static_cast<std::size_t>(worker)];
    const auto cause = [&slot]() -> episode_status::StopCause {
      std::lock_guard<std::mutex> lock(slot.mutex);
      if (!slot.timed_out) return episode_status::stopCause();
      std::ostringstream reason;
      reason << "wall-clock timeout: the run ran longer than " << slot.timeout << " s";
      return {std::string(episode_status::kAborted), reason.str()};
    };
    while (!stop.load()) {
      const std::size_t item = next.fetch_add(1);
      if (item >= count) break;
      {
        std::lock_guard<std::mutex> lock(slot.mutex);
        slot.busy = true;
        slot.timed_out = false;
        slot.timeout = timeout_of(item);
        slot.deadline.reset();
        if (slot.timeout > 0.0)
          slot.deadline =
              std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                     std::chrono::duration<double>(slot.timeout));
      }
      slot.stop.store(stop.load());
      codes[item] = run(worker, item, slot.stop, cause);
      std::lock_guard<std::mutex> lock(slot.mutex);
      slot.busy = false;
      slot.deadline.reset();
    }
    std::lock_guard<std::mutex> lock(done_mutex);
    --running;
    done_changed.notify_all();
  };

  std::vector<std::thread> threads;
  threads.reserve(static_cast<std::size_t>(jobs));
  for (int w = 0; w < jobs; ++w) threads.emplace_back(work, w);
  // The watch: a signal stops every item at once; a deadline stops its own item. Checked ten
  // times a second (an item checks its flag every tick).
  {
    std::unique_lock<std::mutex> lock(done_mutex);
    while (running > 0) {
      done_changed.wait_for(lock, std::chrono::milliseconds(100));
      const auto now = std::chrono::steady_clock::now();
      for (auto& slot : slots) {
        std::lock_guard<std::mutex> slot_lock(slot.mutex);
        if (slot.deadline && now >= *slot.deadline && !slot.timed_out && !slot.stop.load()) {
          slot.timed_out = true;  // before the flag: the item reads its cause once stopped
          slot.stop.store(true);
        } else if (stop.load() && slot.busy) {
          slot.stop.store(true);
        }
      }
    }
  }
  for (auto& t : threads) t.join();
  return codes;
}

}  // namespace hunav::runner
