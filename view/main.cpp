// hunav_view: a web page that shows a run live (or a replay of one) and edits scenarios.
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/signals.hpp"
#include "hunav/view/live_feed.hpp"
#include "hunav/view/netns.hpp"
#include "hunav/view/replay.hpp"
#include "hunav/view/server.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_view: a local web server that shows a run live (its LCM bus), replays a results folder or an LCM log, "
      "and edits scenarios (view/README.md). Open the URL it prints in a browser."};
  std::string url, scenario_file, results_dir, log_file, host = "127.0.0.1", editor_dir = ".";
  int port = 8765;
  long netns_pid = 0;
  double fps = 30.0, netns_wait = 30.0;
  bool no_live = false, no_editor = false;
  app.add_option("--lcm-url", url,
                 "LCM URL of the run to show (default: $LCM_DEFAULT_URL, else udpm on this host only)");
  app.add_option("--scenario", scenario_file,
                 "the run's scenario file, for the map (static geometry is not on the bus); default: the file the "
                 "run's EPISODE_EVENT names, or the one in the results' run.json");
  auto* results = app.add_option("--results", results_dir, "replay a results folder (states.csv, run.json)");
  auto* log_opt = app.add_option("--log", log_file, "replay an LCM log (run_experiment.sh --record's run.lcmlog)");
  results->excludes(log_opt);
  app.add_flag("--no-live", no_live, "no live view (the editor only)");
  app.add_option("--host", host, "address to listen on (default 127.0.0.1: this machine only)");
  app.add_option("--port", port, "port to listen on (0: any free port; the URL is printed)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--editor", editor_dir,
                 "the scenario editor's folder: it reads and writes only inside it (default: .)");
  app.add_flag("--no-editor", no_editor, "no scenario editor");
  app.add_option("--fps", fps, "live frames sent per second, at most")->check(CLI::Range(1.0, 120.0));
  app.add_option("--netns-pid", netns_pid,
                 "after opening the HTTP socket here, join the network namespace of this process for LCM (the "
                 "run_experiment.sh process of a run; it waits until the process has one of its own), and exit with it")
      ->check(hunav::cli::positiveInteger());
  app.add_option("--netns-wait", netns_wait, "s to wait for that namespace and its bus")
      ->check(CLI::Range(0.1, 3600.0));
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;

  const auto& stop = hunav::installStopSignals();
  return hunav::cli::run("hunav_view", [&] {
    using namespace hunav::view;
    if (host != "127.0.0.1" && host != "localhost" && host != "::1")
      std::cerr << "hunav_view: warning: listening on " << host
                << ": anyone who can reach it sees the run and can read and write scenarios in the editor's folder\n";
    SceneStore scene;
    std::optional<Replay> replay;
    if (!results_dir.empty()) replay = loadResults(results_dir);
    if (!log_file.empty()) replay = loadLog(log_file);
    if (!scenario_file.empty()) {
      if (!scene.load(scenario_file)) hunav::loadScenario(scenario_file);  // rethrows the loader's error: exit 2
    } else if (replay && !replay->scenario_file.empty()) {
      if (!scene.load(replay->scenario_file))
        std::cerr << "hunav_view: cannot load the run's scenario " << replay->scenario_file
                  << " (the map is left out; give --scenario FILE)\n";
    }
    std::unique_ptr<Editor> editor;
    if (!no_editor) editor = std::make_unique<Editor>(editor_dir);
    const bool live = !replay && !no_live;
    FrameHub hub;
    ServerParts parts;
    parts.scene = &scene;
    parts.live = live ? &hub : nullptr;
    parts.replay = replay ? &*replay : nullptr;
    parts.editor = editor.get();
    ViewServer server(parts);
    // The socket opens in this thread's namespace (the host's) before any namespace is joined.
    const int bound = server.bind(host, port);
    const std::string shown_host = host.find(':') != std::string::npos ? "[" + host + "]" : host;
    std::cout << "hunav_view: open http://" << shown_host << ":" << bound << "/ in a browser" << std::endl;

    std::unique_ptr<hunav::Bus> bus;
    std::unique_ptr<LiveFeed> feed;
    if (live) {
      const auto wait = std::chrono::milliseconds(static_cast<long>(netns_wait * 1000));
      const auto deadline = std::chrono::steady_clock::now() + wait;
      if (netns_pid > 0) {
        joinNetworkNamespaceOf(static_cast<pid_t>(netns_pid), wait);
        // The run's script routes multicast a moment later: wait for it rather than let LCM complain.
        while (!multicastRouted() && std::chrono::steady_clock::now() < deadline && !stop.load())
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      hunav::ReceiveOptions receive;
      receive.filter_unsubscribed_channels = true;  // the kernel drops what the view ignores
      receive.min_wake_interval = std::chrono::milliseconds(2);
      for (;;) {
        try {
          bus = hunav::openBus(hunav::resolveLcmUrl(url), receive);
          break;
        } catch (const std::exception& e) {
          // In a run's namespace the multicast route comes a moment after the namespace.
          if (netns_pid == 0 || std::chrono::steady_clock::now() > deadline || stop.load())
            throw std::runtime_error(std::string("cannot open the LCM bus: ") + e.what());
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
      }
      LiveOptions live_options;
      live_options.fps = fps;
      feed = std::make_unique<LiveFeed>(*bus, hub, scene, live_options);
    }
    std::thread http([&server] { server.serve(); });
    std::cout << "ready" << std::endl;
    while (!stop.load()) {
      if (bus)
        bus->handleFor(std::chrono::milliseconds(100));
      else
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      if (netns_pid > 0 && !processAlive(static_cast<pid_t>(netns_pid))) break;  // the run is over
    }
    server.stop();
    http.join();
    if (feed)
      std::cerr << "hunav_view: " << feed->worldStates() << " world states received, " << feed->framesBuilt()
                << " frames sent\n";
    return 0;
  });
}
