#include "hunav/view/server.hpp"

#include <httplib.h>

#include <cstring>
#include <iostream>
#include <thread>

#include "hunav/config_error.hpp"

namespace hunav::view {

namespace {

void sendJson(httplib::Response& res, const Json& body, int status = 200) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(), "application/json");
}

void sendError(httplib::Response& res, int status, const std::string& what) {
  sendJson(res, {{"error", what}}, status);
}

// The JSON body of a POST, or an answer 400 and nullopt.
std::optional<Json> body(const httplib::Request& req, httplib::Response& res) {
  Json j = Json::parse(req.body, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) {
    sendError(res, 400, "the request body must be a JSON object");
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

}  // namespace

ViewServer::ViewServer(ServerParts parts) : parts_(parts), server_(std::make_unique<httplib::Server>()) {
  // Each streaming page holds a thread: room for several pages and the API at once.
  server_->new_task_queue = [] { return new httplib::ThreadPool(16); };
  server_->set_payload_max_length(16u << 20);  // a scenario document: far below
  server_->set_keep_alive_max_count(100);
  routes();
}

ViewServer::~ViewServer() { stop(); }

int ViewServer::bind(const std::string& host, int port) {
  const int bound = port == 0 ? server_->bind_to_any_port(host) : (server_->bind_to_port(host, port) ? port : -1);
  if (bound <= 0)
    throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) + ": " + std::strerror(errno) +
                             " (another program on that port? --port 0 takes any free port)");
  return bound;
}

void ViewServer::serve() { server_->listen_after_bind(); }

void ViewServer::stop() {
  if (parts_.live != nullptr) parts_.live->close();
  // Streams end their responses cleanly (the hub is closed) before the sockets close: up to 0.5 s.
  for (int i = 0; i < 50 && streams_.load() > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  stopping_ = true;
  if (server_) server_->stop();
}

void ViewServer::routes() {
  routeAssets();
  routeRun();
  routeEditor();
  routeErrors();
}

void ViewServer::routeAssets() {
  httplib::Server& s = *server_;
  for (int i = 0; i < kWebAssetCount; ++i) {
    const WebAsset asset = kWebAssets[i];
    auto handler = [asset](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-store");
      res.set_content(asset.body, asset.content_type);
    };
    s.Get(asset.path, handler);
    if (std::strcmp(asset.path, "/index.html") == 0) s.Get("/", handler);
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
    std::string frame = parts_.live->latest();
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
    sendJson(res, parts_.replay->data);
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
    const std::string planner = j->value("planner", parts_.default_planner);
    const double duration =
        j->contains("duration") && (*j)["duration"].is_number() ? (*j)["duration"].get<double>() : 0.0;
    sendJson(res, e->run(*path, planner, duration));
  });
  s.Get("/api/editor/replay", [editor](const httplib::Request& req, httplib::Response& res) {
    Editor* e = editor(res);
    if (e == nullptr) return;
    if (!req.has_param("path")) return sendError(res, 400, "missing query parameter 'path'");
    const auto dir = e->resolve(req.get_param_value("path"), false);
    if (!std::filesystem::is_directory(dir)) return sendError(res, 404, "no such results folder");
    sendJson(res, loadResults(dir).data);
  });
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
    else
      sendError(res, res.status, "bad request");
  });
}

}  // namespace hunav::view
