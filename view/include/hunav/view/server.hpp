#pragma once
// hunav_view's HTTP server (cpp-httplib): the page (embedded at build time from view/web/), the
// scene, live frames as server-sent events, a replay, and the editor's API. Every answer of the API
// is JSON; a bad request gets {"error": "..."} with status 400 (403 for a path outside the editor's
// folder, 404 for what does not exist), and no request can stop the server.
#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "hunav/view/editor.hpp"
#include "hunav/view/live_feed.hpp"
#include "hunav/view/replay.hpp"

namespace httplib {
class Server;
}

namespace hunav::view {

struct ServerParts {
  SceneStore* scene = nullptr;          // required
  FrameHub* live = nullptr;             // live mode: frames to stream
  const Replay* replay = nullptr;       // replay mode
  Editor* editor = nullptr;             // the editor's folder (null: no editor)
  std::string default_planner = "dwb";  // for the editor's runs
};

class ViewServer {
 public:
  explicit ViewServer(ServerParts parts);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  // Opens the listening socket (port 0: any free port) in the calling thread's network namespace and
  // returns the port. Throws std::runtime_error when it cannot.
  int bind(const std::string& host, int port);
  // Serves until stop() (blocks; call after bind()).
  void serve();
  void stop();
  // Connections streaming live frames now.
  int streams() const { return streams_.load(); }

 private:
  void routes();
  void routeAssets();
  void routeRun();
  void routeEditor();
  void routeErrors();
  ServerParts parts_;
  std::unique_ptr<httplib::Server> server_;
  std::atomic<bool> stopping_{false};
  std::atomic<int> streams_{0};
};

// The page's files, embedded at build time (web_assets.cpp, generated from view/web/).
struct WebAsset {
  const char* path;
  const char* content_type;
  const char* body;
};
extern const WebAsset kWebAssets[];
extern const int kWebAssetCount;

}  // namespace hunav::view
