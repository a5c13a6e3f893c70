#include "hunav/view/server.hpp"

#include <httplib.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <random>
#include <thread>

#include "hunav/config_error.hpp"
#include "hunav/embedded_files.hpp"
#include "hunav/message_checks.hpp"

namespace hunav::view {

// The page: view/web/ as it was at build time (CMakeLists.txt, hunav_embed_files).
extern const EmbeddedFiles kWebFiles;

namespace {

// The Content-Type of a page file, by its extension.
std::string contentTypeOf(const std::string& path) {
  const auto endsWith = [&path](const std::string& ext) {
    return path.size() >= ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
  };
  if (endsWith(".html")) return "text/html; charset=utf-8";
  if (endsWith(".js")) return "text/javascript; charset=utf-8";
  if (endsWith(".css")) return "text/css; charset=utf-8";
  return "application/octet-stream";
}

void sendJson(httplib::Response& res, const Json& body, int status = 200) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(jsonText(body), "application/json");
}

void sendError(httplib::Response& res, int status, const std::string& what) {
  sendJson(res, {{"error", what}}, status);
}

// Chunk `i` of a replay (query parameter), as stored (gzip) to a client that accepts gzip, else
// decompressed. "; charset=utf-8" keeps cpp-httplib from compressing it again: its gzip of a whole
// replay took 20-30 s (0.11.4, 15 MB) where zlib takes 0.1 s.
void sendChunk(const httplib::Request& req, httplib::Response& res, const Replay& replay) {
  const std::string text = req.has_param("i") ? req.get_param_value("i") : std::string();
  std::size_t i = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), i);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size())
    return sendError(res, 400, "query parameter 'i' must be a chunk index");
  if (i >= replay.chunks.size())
    return sendError(res, 404, "no chunk " + text + " (the replay has " + std::to_string(replay.chunks.size()) + ")");
  res.set_header("Cache-Control", "no-store");
  res.set_header("Vary", "Accept-Encoding");
  if (req.get_header_value("Accept-Encoding").find("gzip") != std::string::npos) {
    res.set_header("Content-Encoding", "gzip");
    res.set_content(replay.chunks[i].gzip, "application/json; charset=utf-8");
  } else {
    res.set_content(replay.chunkText(i), "application/json; charset=utf-8");
  }
}

// True when the JSON text nests arrays and objects at most `max_depth` deep (strings skipped): checked
// before parsing, whose recursion a deep document (a few hundred KB of '[') would overflow.
bool nestsAtMost(const std::string& text, int max_depth) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return false;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return true;
}

// The JSON body of a POST, or an answer 400 and nullopt.
std::optional<Json> body(const httplib::Request& req, httplib::Response& res) {
  if (req.body.size() > ViewServer::kMaxBodyBytes) {
    sendError(res, 413, "the request body is larger than " + std::to_string(ViewServer::kMaxBodyBytes) + " bytes");
    return std::nullopt;
  }
  if (!nestsAtMost(req.body, ViewServer::kMaxJsonDepth)) {
    sendError(res, 400, "the request body nests deeper than " + std::to_string(ViewServer::kMaxJsonDepth) + " levels");
    return std::nullopt;
  }
  // The parser refuses text that is not UTF-8.
  Json j = Json::parse(req.body, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) {
    sendError(res, 400, "the request body must be a JSON object (UTF-8)");
    return std::nullopt;
  }
  return j;
}

// A string field of a JSON object, or an answer 400 and nullopt.
std::optional<std::string> stringField(const Json& j, const char* key, httplib::Response& res) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_string()) {
    sendError(res, 400, std::string("missing string field '") + key + "'");
    return std::nullopt;
  }
  return it->get<std::string>();
}

// The {path, doc} body of an editor request (validate, save), or an answer 400 and nullopt.
// {path, doc, people_doc?}: a scenario document and, optionally, its agents file's.
struct DocRequest {
  std::string path;
  Json doc;
  Json people_doc;
};

std::optional<DocRequest> docRequest(const httplib::Request& req, httplib::Response& res) {
  auto j = body(req, res);
  if (!j) return std::nullopt;
  auto path = stringField(*j, "path", res);
  if (!path) return std::nullopt;
  if (!j->contains("doc")) {
    sendError(res, 400, "missing field 'doc'");
    return std::nullopt;
  }
  return DocRequest{*path, (*j)["doc"], j->value("people_doc", Json(nullptr))};
}

// A fresh random token (128 bits, hex) for this start of the server.
std::string newToken() {
  std::random_device device;
  std::string token;
  char hex[9];
  for (int i = 0; i < 4; ++i) {
    std::snprintf(hex, sizeof hex, "%08x", static_cast<unsigned>(device()));
    token += hex;
  }
  return token;
}

bool isLoopback(const std::string& host) { return host == "127.0.0.1" || host == "localhost" || host == "::1"; }
bool isWildcard(const std::string& host) { return host == "0.0.0.0" || host == "::" || host.empty(); }

}  // namespace

ViewServer::ViewServer(ServerParts parts)
    : parts_(parts), server_(std::make_unique<httplib::Server>()), token_(newToken()) {
  // Each streaming page holds a thread: room for several pages and the API at once.
  server_->new_task_queue = [] { return new httplib::ThreadPool(16); };
  server_->set_payload_max_length(kMaxBodyBytes);
  server_->set_keep_alive_max_count(100);
  routes();
}

ViewServer::~ViewServer() { stop(); }

int ViewServer::bind(const std::string& host, int port) {
  const int bound = port == 0 ? server_->bind_to_any_port(host) : (server_->bind_to_port(host, port) ? port : -1);
  if (bound <= 0)
    throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) + ": " + std::strerror(errno) +
                             " (another program on that port? --port 0 takes any free port)");
  // The names a browser reaching this socket sends as Host (and, with "http://", as Origin).
  allowed_hosts_.clear();
  any_host_ = isWildcard(host);
  std::vector<std::string> names = {host.find(':') != std::string::npos ? "[" + host + "]" : host};
  if (isLoopback(host)) names = {"127.0.0.1", "localhost", "[::1]"};
  for (const auto& name : names) {
    allowed_hosts_.push_back(name + ":" + std::to_string(bound));
    if (bound == 80) allowed_hosts_.push_back(name);
  }
  return bound;
}

bool ViewServer::hostAllowed(const std::string& host) const {
  if (any_host_) return !host.empty();
  for (const auto& h : allowed_hosts_)
    if (h == host) return true;
  return false;
}

bool ViewServer::admit(const httplib::Request& req, httplib::Response& res) const {
  // Host: a page of another site that makes its name resolve to this machine (DNS rebinding) sends its own.
  const std::string host = req.get_header_value("Host");
  if (!hostAllowed(host)) {
    sendError(res, 403,
              "refused: a request for host '" + host.substr(0, 100) + "' (this server answers for " +
                  (allowed_hosts_.empty() ? std::string("its own address") : allowed_hosts_.front()) + " only)");
    return false;
  }
  // Origin: browsers send it with every cross-origin request, and with same-origin POSTs.
  if (req.has_header("Origin")) {
    const std::string origin = req.get_header_value("Origin");
    const std::string prefix = "http://";
    if (origin.compare(0, prefix.size(), prefix) != 0 || !hostAllowed(origin.substr(prefix.size()))) {
      sendError(res, 403, "refused: a cross-origin request (Origin '" + origin.substr(0, 100) + "')");
      return false;
    }
  }
  if (!isUtf8(req.path)) {
    sendError(res, 400, "the path is not UTF-8");
    return false;
  }
  for (const auto& kv : req.params) {
    if (!isUtf8(kv.first) || !isUtf8(kv.second)) {
      sendError(res, 400, "a query parameter is not UTF-8");
      return false;
    }
  }
  if (req.method == "GET" || req.method == "HEAD") return true;
  // Writes and runs: only from this start's page, which carries the token (another site can neither
  // read the page nor send a custom header without a preflight this server never grants).
  if (req.get_header_value(kTokenHeader) != token_) {
    sendError(res, 403,
              std::string("refused: missing or wrong ") + kTokenHeader +
                  " (the page sends it; reload the page after hunav_view restarts)");
    return false;
  }
  if (req.get_header_value("Content-Type").rfind("application/json", 0) != 0) {
    sendError(res, 415, "the request body must be sent as application/json");
    return false;
  }
  return true;
}

void ViewServer::serve() { server_->listen_after_bind(); }

bool ViewServer::listening() const { return server_->is_running(); }

void ViewServer::stop() {
  if (parts_.live != nullptr) parts_.live->close();
  // Streams end their responses cleanly (the hub is closed) before the sockets close: up to 0.5 s.
  for (int i = 0; i < 50 && streams_.load() > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  stopping_ = true;
  if (server_) server_->stop();
}

void ViewServer::routes() {
  // Every request passes admit() first: an answer from it ends the request.
  server_->set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    return admit(req, res) ? httplib::Server::HandlerResponse::Unhandled : httplib::Server::HandlerResponse::Handled;
  });
  routeAssets();
  routeRun();
  routeEditor();
  routeErrors();
}

void ViewServer::routeAssets() {
  httplib::Server& s = *server_;
  for (const EmbeddedFile& file : kWebFiles) {
    const std::string path = "/" + std::string(file.name);
    // The page carries this start's token (a meta element) for the API's writes.
    std::string body(file.text);
    for (std::size_t at; (at = body.find(kTokenPlaceholder)) != std::string::npos;)
      body.replace(at, std::strlen(kTokenPlaceholder), token_);
    auto handler = [body = std::move(body), type = contentTypeOf(path)](const httplib::Request&,
                                                                        httplib::Response& res) {
      res.set_header("Cache-Control", "no-store");
      res.set_content(body, type.c_str());
    };
    s.Get(path, handler);
    if (path == "/index.html") s.Get("/", handler);
  }

  // Browsers ask for an icon: none, rather than a 404 in the page's console.
  s.Get("/favicon.ico", [](const httplib::Request&, httplib::Response& res) { res.status = 204; });
}

// What the page shows: the mode, the scene, the live frames (latest, or a stream) or the replay.
void ViewServer::routeRun() {
  httplib::Server& s = *server_;
  s.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
    std::string mode = parts_.live ? "live" : parts_.replay ? "replay" : "editor";
    sendJson(res, {{"mode", mode},
                   {"editor", parts_.editor != nullptr},
                   {"editor_root", parts_.editor ? parts_.editor->root().string() : ""},
                   {"scene_version", parts_.scene->version()}});
  });
  s.Get("/api/scene", [this](const httplib::Request&, httplib::Response& res) { sendJson(res, parts_.scene->get()); });
  s.Get("/api/frame", [this](const httplib::Request&, httplib::Response& res) {
    if (parts_.live == nullptr) return sendError(res, 404, "not a live view (started with --results or --log)");
    std::string frame = parts_.live->latest();  // built by jsonText's rules (frames.hpp)
    if (frame.empty()) frame = "null";
    res.set_header("Cache-Control", "no-store");
    res.set_content(frame, "application/json");
  });
  s.Get("/api/stream", [this](const httplib::Request&, httplib::Response& res) {
    if (parts_.live == nullptr) return sendError(res, 404, "not a live view (started with --results or --log)");
    res.set_header("Cache-Control", "no-store");
    auto seen = std::make_shared<std::uint64_t>(0);
    ++streams_;
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, seen](std::size_t, httplib::DataSink& sink) {
          if (stopping_) return false;
          // The latest frame when there is a newer one than this page has: the frames in between are
          // skipped, so a slow page costs nobody but itself.
          auto frame = parts_.live->waitNewer(*seen, std::chrono::milliseconds(1000));
          if (!frame && parts_.live->closed()) {
            sink.done();  // the end of the response, not a broken one
            return true;
          }
          std::string msg = frame ? "data: " + *frame + "\n\n" : std::string(": idle\n\n");
          if (stopping_ || !sink.is_writable()) return false;
          return sink.write(msg.data(), msg.size());
        },
        [this](bool) { --streams_; });
  });
  s.Get("/api/replay", [this](const httplib::Request&, httplib::Response& res) {
    if (parts_.replay == nullptr) return sendError(res, 404, "not a replay (start with --results DIR or --log FILE)");
    sendJson(res, parts_.replay->header());
  });
  s.Get("/api/replay/chunk", [this](const httplib::Request& req, httplib::Response& res) {
    if (parts_.replay == nullptr) return sendError(res, 404, "not a replay (start with --results DIR or --log FILE)");
    sendChunk(req, res, *parts_.replay);
  });
}

// The scenario editor. A PathError is a refusal (403), a missing file 404.
void ViewServer::routeEditor() {
  httplib::Server& s = *server_;
  auto editor = [this](httplib::Response& res) -> Editor* {
    if (parts_.editor == nullptr) sendError(res, 404, "no editor (start hunav_view with --editor DIR)");
    return parts_.editor;
  };
  s.Get("/api/editor/files", [editor](const httplib::Request&, httplib::Response& res) {
    if (Editor* e = editor(res)) sendJson(res, {{"root", e->root().string()}, {"files", e->files()}});
  });
  s.Get("/api/editor/open", [editor](const httplib::Request& req, httplib::Response& res) {
    Editor* e = editor(res);
    if (e == nullptr) return;
    if (!req.has_param("path")) return sendError(res, 400, "missing query parameter 'path'");
    sendJson(res, e->open(req.get_param_value("path")));
  });
  s.Post("/api/editor/validate", [editor](const httplib::Request& req, httplib::Response& res) {
    Editor* e = editor(res);
    if (e == nullptr) return;
    if (auto d = docRequest(req, res)) sendJson(res, e->validate(d->path, d->doc, d->people_doc));
  });
  s.Post("/api/editor/save", [editor](const httplib::Request& req, httplib::Response& res) {
    Editor* e = editor(res);
    if (e == nullptr) return;
    // A scenario the loader rejects is an answer ({ok: false, error}), not a failed request.
    if (auto d = docRequest(req, res)) sendJson(res, e->save(d->path, d->doc, d->people_doc));
  });
  s.Post("/api/editor/run", [this, editor](const httplib::Request& req, httplib::Response& res) {
    Editor* e = editor(res);
    if (e == nullptr) return;
    auto j = body(req, res);
    if (!j) return;
    auto path = stringField(*j, "path", res);
    if (!path) return;
    std::string planner = parts_.default_planner;
    if (j->contains("planner")) {
      auto given = stringField(*j, "planner", res);
      if (!given) return;
      planner = *given;
    }
    double duration = 0.0;
    if (j->contains("duration") && !(*j)["duration"].is_null()) {
      if (!(*j)["duration"].is_number()) return sendError(res, 400, "duration must be a number");
      duration = (*j)["duration"].get<double>();
    }
    sendJson(res, e->run(*path, planner, duration));
  });
  // A results folder of the editor's, as /api/replay and /api/replay/chunk.
  const auto editorReplayOf = [this, editor](const httplib::Request& req, httplib::Response& res,
                                             bool reload) -> std::shared_ptr<const Replay> {
    Editor* e = editor(res);
    if (e == nullptr) return nullptr;
    if (!req.has_param("path")) {
      sendError(res, 400, "missing query parameter 'path'");
      return nullptr;
    }
    const auto dir = e->resolve(req.get_param_value("path"), false);
    if (!std::filesystem::is_directory(dir)) {
      sendError(res, 404, "no such results folder");
      return nullptr;
    }
    return editorReplay(dir, reload);
  };
  s.Get("/api/editor/replay", [editorReplayOf](const httplib::Request& req, httplib::Response& res) {
    if (auto replay = editorReplayOf(req, res, true)) sendJson(res, replay->header());
  });
  s.Get("/api/editor/replay/chunk", [editorReplayOf](const httplib::Request& req, httplib::Response& res) {
    if (auto replay = editorReplayOf(req, res, false)) sendChunk(req, res, *replay);
  });
}

std::shared_ptr<const Replay> ViewServer::editorReplay(const std::filesystem::path& dir, bool reload) {
  std::lock_guard<std::mutex> lock(editor_replay_mutex_);
  if (reload || !editor_replay_ || editor_replay_dir_ != dir) {
    editor_replay_ = std::make_shared<const Replay>(loadResults(dir, parts_.replay_options));
    editor_replay_dir_ = dir;
  }
  return editor_replay_;
}

// Errors as JSON: a refused path 403, a rejected scenario 422, a bad request 400, anything else 500.
void ViewServer::routeErrors() {
  httplib::Server& s = *server_;
  s.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
    try {
      std::rethrow_exception(ep);
    } catch (const PathError& e) {
      sendError(res, 403, e.what());
    } catch (const ConfigError& e) {
      sendError(res, 422, e.what());
    } catch (const std::invalid_argument& e) {
      sendError(res, 400, e.what());
    } catch (const std::exception& e) {
      sendError(res, 500, e.what());
    } catch (...) {
      sendError(res, 500, "unknown error");
    }
  });
  s.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;
    if (res.status == 404)
      sendError(res, 404, "no such page or API: " + req.path);
    else if (res.status == 413)
      sendError(res, 413, "the request body is larger than " + std::to_string(kMaxBodyBytes) + " bytes");
    else
      sendError(res, res.status, "bad request");
  });
}

namespace {

// serve() on a thread of its own, stopped and joined when this goes out of scope (an exception
// included).
class ServingThread {
 public:
  explicit ServingThread(ViewServer& server)
      : server_(server), thread_([this] {
          server_.serve();
          returned_ = true;
        }) {}
  ~ServingThread() {
    // httplib's stop() does nothing before serve() has begun to listen, which would then never end:
    // wait for that (or for serve() to have returned, when it could not listen).
    while (!server_.listening() && !returned_.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    server_.stop();
    thread_.join();
  }
  ServingThread(const ServingThread&) = delete;
  ServingThread& operator=(const ServingThread&) = delete;

 private:
  ViewServer& server_;
  std::atomic<bool> returned_{false};  // before thread_, which sets it
  std::thread thread_;
};

}  // namespace

void serveUntilStopped(ViewServer& server, Bus* bus, const std::atomic<bool>& stop,
                       const std::function<bool()>& keep_going) {
  ServingThread http(server);
  while (!stop.load()) {
    if (bus != nullptr)
      bus->handleFor(std::chrono::milliseconds(100));
    else
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (!keep_going()) break;
  }
}

}  // namespace hunav::view
