#pragma once
// hunav_view's HTTP server (cpp-httplib): the page (embedded at build time from view/web/), the
// scene, live frames as server-sent events, a replay, and the editor's API. Every answer of the API
// is JSON; a bad request gets {"error": "..."} with status 400 (403 for a path outside the editor's
// folder or a refused origin, 404 for what does not exist, 413 for a body too large), and no request
// can stop the server: every handler is behind one error boundary, and text that is not UTF-8 is
// refused at the edge (query parameters, bodies) or sent with U+FFFD in place of its bad bytes.
// 127.0.0.1 is no boundary against the user's own browser, so every request passes admit(): its Host
// (and Origin, when sent) must name this server; writes and runs (POST) must carry the token of this
// start, which only the page served here holds (a <meta name="hunav-token"> element).
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "hunav/bus.hpp"
#include "hunav/view/editor.hpp"
#include "hunav/view/live_feed.hpp"
#include "hunav/view/replay.hpp"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace hunav::view {

struct ServerParts {
  SceneStore* scene = nullptr;          // required
  FrameHub* live = nullptr;             // live mode: frames to stream
  const Replay* replay = nullptr;       // replay mode
  Editor* editor = nullptr;             // the editor's folder (null: no editor)
  ReplayOptions replay_options;         // for the replays of the editor's runs
  std::string default_planner = "dwb";  // for the editor's runs
};

class ViewServer {
 public:
  // A POST body is refused (413) beyond this size, and (400) when it nests arrays and objects deeper
  // than this, before it is parsed.
  static constexpr std::size_t kMaxBodyBytes = 8u << 20;  // a scenario document: far below
  static constexpr int kMaxJsonDepth = 256;               // a YAML map is 3 JSON levels ({"__map": [[k, v]]})
  // The header of a POST that carries the page's token, and the placeholder of the page it replaces.
  static constexpr const char* kTokenHeader = "X-HuNav-Token";
  static constexpr const char* kTokenPlaceholder = "__HUNAV_TOKEN__";

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
  // True while serve() listens (from its start until stop() ends it).
  bool listening() const;
  // Connections streaming live frames now.
  int streams() const { return streams_.load(); }
  // This start's token (random, 128 bits): the page's POSTs send it in kTokenHeader.
  const std::string& token() const { return token_; }

 private:
  void routes();
  void routeAssets();
  void routeRun();
  void routeEditor();
  void routeErrors();
  // The request policy above: true to go on, false with the refusal answered.
  bool admit(const httplib::Request& req, httplib::Response& res) const;
  bool hostAllowed(const std::string& host) const;
  // The replay of a results folder of the editor's: loaded again when `reload` (the page opens a run)
  // or when it is not the folder loaded last; its chunks are fetched one request each.
  std::shared_ptr<const Replay> editorReplay(const std::filesystem::path& dir, bool reload);
  ServerParts parts_;
  std::unique_ptr<httplib::Server> server_;
  std::string token_;
  std::vector<std::string> allowed_hosts_;  // host:port names of this socket (bind())
  bool any_host_ = false;                   // bound to every address (0.0.0.0, ::): any Host
  std::atomic<bool> stopping_{false};
  std::atomic<int> streams_{0};
  std::mutex editor_replay_mutex_;
  std::filesystem::path editor_replay_dir_;
  std::shared_ptr<const Replay> editor_replay_;
};

// hunav_view's loop: serves HTTP on a thread of its own and, until `stop` is set or `keep_going`
// returns false, dispatches the messages of `bus` (null: none; the loop only waits). However the loop
// ends, the server is stopped and its thread joined first: an exception (of the bus, of a handler)
// is rethrown after the join, instead of destroying a joinable thread (std::terminate).
void serveUntilStopped(ViewServer& server, Bus* bus, const std::atomic<bool>& stop,
                       const std::function<bool()>& keep_going);

}  // namespace hunav::view
