// hunav_view: a web page that shows a run live (or a replay of one) and edits scenarios.
#include <sys/resource.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/signals.hpp"
#include "hunav/view/live_feed.hpp"
#include "hunav/view/netns.hpp"
#include "hunav/view/replay.hpp"
#include "hunav/view/server.hpp"

namespace {

using namespace hunav::view;

// Everything the command line says.
struct Options {
  std::string url, scenario_file, results_dir, log_file, host = "127.0.0.1", editor_dir = ".";
  int port = 8765;
  long netns_pid = 0;
  double fps = 30.0, netns_wait = 30.0;
  bool no_live = false, no_editor = false;
  ReplayOptions replay;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--lcm-url", o.url,
                 "LCM URL of the run to show (default: $LCM_DEFAULT_URL, else udpm on this host only)");
  app.add_option("--scenario", o.scenario_file,
                 "the run's scenario file, for the map (static geometry is not on the bus); default: the file the "
                 "run's EPISODE_EVENT names, or the one in the results' run.json");
  auto* results = app.add_option("--results", o.results_dir, "replay a results folder (states.csv, run.json)");
  auto* log_opt = app.add_option("--log", o.log_file, "replay an LCM log (run_experiment.sh --record's run.lcmlog)");
  results->excludes(log_opt);
  app.add_option("--replay-rate", o.replay.rate,
                 "replay frames kept per second of simulation time, at most (0: every sample; a crowd keeps fewer: "
                 "at most --replay-rows rows per second); default 20")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--replay-rows", o.replay.max_rows_per_second,
                 "replay rows (robot and people) kept per second of simulation time, at most (0: no limit); default "
                 "10000")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1'000'000'000}));
  app.add_option("--replay-chunk-seconds", o.replay.chunk_seconds,
                 "a replay is sent to the page in chunks of at most this many seconds of simulation time (and 1 MB "
                 "of text); default 30")
      ->check(CLI::Range(0.01, 1e6));
  app.add_flag("--no-live", o.no_live, "no live view (the editor only)");
  app.add_option("--host", o.host, "address to listen on (default 127.0.0.1: this machine only)");
  app.add_option("--port", o.port, "port to listen on (0: any free port; the URL is printed)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--editor", o.editor_dir,
                 "the scenario editor's folder: it reads and writes only inside it (default: .)");
  app.add_flag("--no-editor", o.no_editor, "no scenario editor");
  app.add_option("--fps", o.fps, "live frames sent per second, at most")->check(CLI::Range(1.0, 120.0));
  app.add_option("--netns-pid", o.netns_pid,
                 "after opening the HTTP socket here, join the network namespace of this process for LCM (the "
                 "run_experiment.sh process of a run; it waits until the process has one of its own), and exit with it")
      ->check(hunav::cli::positiveInteger());
  app.add_option("--netns-wait", o.netns_wait, "s to wait for that namespace and its bus")
      ->check(CLI::Range(0.1, 3600.0));
}

// The map: --scenario's (a bad file is exit 2), else the one the replayed run names (the map is left
// out when it cannot be loaded).
void loadScene(const Options& o, const std::optional<Replay>& replay, SceneStore& scene) {
  if (!o.scenario_file.empty()) {
    if (!scene.load(o.scenario_file)) hunav::loadScenario(o.scenario_file);  // rethrows the loader's error: exit 2
  } else if (replay && !replay->scenario_file.empty()) {
    if (!scene.load(replay->scenario_file))
      std::cerr << "hunav_view: cannot load the run's scenario " << replay->scenario_file
                << " (the map is left out; give --scenario FILE)\n";
  }
}

// The run's bus, in the run's network namespace with --netns-pid (joined after the HTTP socket was
// opened in the host's). The view only listens: the kernel drops what it ignores, and it reads what
// arrived every 2 ms at most.
std::unique_ptr<hunav::Bus> openLiveBus(const Options& o, const std::atomic<bool>& stop) {
  const auto wait = std::chrono::milliseconds(static_cast<long>(o.netns_wait * 1000));
  const auto deadline = std::chrono::steady_clock::now() + wait;
  if (o.netns_pid > 0) {
    joinNetworkNamespaceOf(static_cast<pid_t>(o.netns_pid), wait);
    // The run's script routes multicast a moment later: wait for it rather than let LCM complain.
    while (!multicastRouted() && std::chrono::steady_clock::now() < deadline && !stop.load())
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  hunav::ReceiveOptions receive;
  receive.filter_unsubscribed_channels = true;
  receive.min_wake_interval = std::chrono::milliseconds(2);
  for (;;) {
    try {
      return hunav::openBus(hunav::resolveLcmUrl(o.url), receive);
    } catch (const std::exception& e) {
      // In a run's namespace the multicast route comes a moment after the namespace.
      if (o.netns_pid == 0 || std::chrono::steady_clock::now() > deadline || stop.load())
        throw std::runtime_error(std::string("cannot open the LCM bus: ") + e.what());
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
}

int run(const Options& o, const std::atomic<bool>& stop) {
  if (o.host != "127.0.0.1" && o.host != "localhost" && o.host != "::1")
    std::cerr << "hunav_view: warning: listening on " << o.host
              << ": anyone who can reach it sees the run and can read and write scenarios in the editor's folder\n";
  SceneStore scene;
  std::optional<Replay> replay;
  if (!o.results_dir.empty()) replay = loadResults(o.results_dir, o.replay);
  if (!o.log_file.empty()) replay = loadLog(o.log_file, o.replay);
  loadScene(o, replay, scene);
  std::unique_ptr<Editor> editor;
  if (!o.no_editor) editor = std::make_unique<Editor>(o.editor_dir);
  const bool live = !replay && !o.no_live;
  FrameHub hub;
  ServerParts parts;
  parts.scene = &scene;
  parts.live = live ? &hub : nullptr;
  parts.replay = replay ? &*replay : nullptr;
  parts.editor = editor.get();
  parts.replay_options = o.replay;
  ViewServer server(parts);
  // The socket opens in this thread's namespace (the host's) before any namespace is joined.
  const int bound = server.bind(o.host, o.port);
  const std::string shown_host = o.host.find(':') != std::string::npos ? "[" + o.host + "]" : o.host;
  std::cout << "hunav_view: open http://" << shown_host << ":" << bound << "/ in a browser" << std::endl;

  std::unique_ptr<hunav::Bus> bus;
  std::unique_ptr<LiveFeed> feed;
  if (live) {
    bus = openLiveBus(o, stop);
    LiveOptions live_options;
    live_options.fps = o.fps;
    feed = std::make_unique<LiveFeed>(*bus, hub, scene, live_options);
  }
  // The socket listens already (bind): a browser that connects now is answered once serving begins.
  std::cout << "ready" << std::endl;
  serveUntilStopped(server, bus.get(), stop, [&o] {
    return o.netns_pid == 0 || processAlive(static_cast<pid_t>(o.netns_pid));  // else the run is over
  });
  if (feed) {
    // What watching cost (docs/performance.md, "Sampling the bus"): the process's CPU, start-up included.
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const auto ms = [](const timeval& t) { return static_cast<double>(t.tv_sec) * 1e3 + t.tv_usec * 1e-3; };
    std::cerr << "hunav_view: " << feed->worldStates() << " world states received, " << feed->statesDecoded()
              << " decoded, " << feed->framesBuilt() << " frames sent, " << feed->undecodable()
              << " sampled messages dropped as undecodable; CPU " << ms(usage.ru_utime) << " ms user, "
              << ms(usage.ru_stime) << " ms system\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_view: a local web server that shows a run live (its LCM bus), replays a results folder or an LCM log, "
      "and edits scenarios (view/README.md). Open the URL it prints in a browser."};
  Options o;
  addOptions(app, o);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  const auto& stop = hunav::installStopSignals();
  return hunav::cli::run("hunav_view", [&] { return run(o, stop); });
}
