// hunav_record: records every message of an LCM bus into an LCM log file, losing none (see
// include/hunav/report/log_recorder.hpp for why not lcm-logger), until SIGINT/SIGTERM. With
// channel_ports=1 in the URL it also listens on the step channels' own ports (hunav/channels.hpp), so
// the log holds every channel of the run, as one log on one port would.
#include <algorithm>
#include <chrono>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "hunav/channels.hpp"
#include "hunav/cli.hpp"
#include "hunav/config_error.hpp"
#include "hunav/open_bus.hpp"
#include "hunav/report/log_recorder.hpp"
#include "hunav/signals.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "hunav_record: records every message on an LCM bus into an LCM log file (lcm-logger's format, "
      "events stamped with the messages' simulation time), with no queue limit so that no message is lost. "
      "With channel_ports=1 in the URL it also records the step channels' own ports. "
      "Prints 'ready' once subscribed; SIGINT/SIGTERM stops it after writing what it has received. Replay "
      "the file with lcm-logplayer, or recompute its metrics with hunav_evaluator --log FILE."};
  std::string out, url, channels = ".*";
  bool print_url = false;
  auto* out_opt = app.add_option("--out", out, "the log file to write (overwritten); required");
  app.add_option("--lcm-url", url,
                 "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(hunav::kDefaultLcmUrl) + ")");
  app.add_option("--channels", channels, "channels to record (LCM regular expression)")->capture_default_str();
  // The scripts ask for the default bus here rather than write it a second time (launch_scripts/lib.sh).
  app.add_flag("--print-url", print_url,
               "print the bus it would record (--lcm-url, else $LCM_DEFAULT_URL, else the default) and exit")
      ->excludes(out_opt);
  if (auto code = hunav::cli::parse(app, argc, argv)) return *code;
  if (print_url) {
    std::cout << hunav::resolveLcmUrl(url) << "\n";
    return 0;
  }
  if (out.empty()) {
    std::cerr << "hunav_record: --out is required (see --help)\n";
    return hunav::kExitBadInput;
  }

  return hunav::cli::run("hunav_record", [&] {
    const auto& stop = hunav::installStopSignals();
    // The URL's port, then each port of its own (the same URL again, and skipped, without channel_ports=1).
    const std::string bus_url = hunav::resolveLcmUrl(url);
    std::vector<std::string> urls{hunav::lcmUrlForChannel(bus_url, hunav::channels::kWorldState)};
    for (const char* channel : hunav::channels::kOwnPortChannels) {
      std::string port_url = hunav::lcmUrlForChannel(bus_url, channel);
      if (std::find(urls.begin(), urls.end(), port_url) == urls.end()) urls.push_back(std::move(port_url));
    }
    std::vector<std::unique_ptr<lcm::LCM>> instances;
    std::vector<lcm::LCM*> listened;
    for (const std::string& port_url : urls) {
      instances.push_back(std::make_unique<lcm::LCM>(port_url));
      if (!instances.back()->good()) {
        std::cerr << "hunav_record: cannot open the LCM bus " << port_url << " (bad URL, or no multicast route?)\n";
        return 1;
      }
      listened.push_back(instances.back().get());
    }
    std::unique_ptr<hunav::report::LogRecorder> recording;
    try {
      recording = std::make_unique<hunav::report::LogRecorder>(listened, out, channels);
    } catch (const std::invalid_argument& e) {  // a --channels expression LCM cannot compile
      std::cerr << "hunav_record: " << e.what() << "\n";
      return hunav::kExitBadInput;
    }
    hunav::report::LogRecorder& recorder = *recording;
    std::cout << "ready" << std::endl;
    auto last_flush = std::chrono::steady_clock::now();
    while (!stop.load()) {
      recorder.handle(std::chrono::milliseconds(100));
      if (std::chrono::steady_clock::now() - last_flush > std::chrono::milliseconds(500)) {
        recorder.flush();
        last_flush = std::chrono::steady_clock::now();
      }
    }
    // What arrived before the stop request is still queued: write it, until the bus is quiet.
    recorder.drain(std::chrono::milliseconds(200));
    std::cout << "hunav_record: " << recorder.events() << " events in " << out << ":";
    for (const auto& [channel, count] : recorder.eventsPerChannel()) std::cout << " " << channel << " " << count;
    std::cout << std::endl;
    return 0;
  });
}
