#include "hunav/view/editor.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

#include "hunav/config_error.hpp"
#include "hunav/planners/planner.hpp"
#include "hunav/results/metrics_csv.hpp"
#include "hunav/runner/in_process_run.hpp"

namespace hunav::view {

namespace fs = std::filesystem;

namespace {

Json toJson(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: {
      Json j = Json::object();
      // nlohmann::json sorts keys; the order is kept in a side list "__order" would leak into the
      // page, so maps travel as {"__map": [[key, value], ...]} to keep the file's order.
      Json pairs = Json::array();
      for (const auto& kv : n) pairs.push_back(Json::array({kv.first.as<std::string>(), toJson(kv.second)}));
      j["__map"] = std::move(pairs);
      return j;
    }
    case YAML::NodeType::Sequence: {
      Json j = Json::array();
      for (const auto& item : n) j.push_back(toJson(item));
      return j;
    }
    case YAML::NodeType::Scalar:
      return n.Scalar();
    default:
      return nullptr;
  }
}

bool isScalar(const Json& j) { return !j.is_array() && !(j.is_object()); }

bool allScalars(const Json& j) {
  if (j.is_array()) return std::all_of(j.begin(), j.end(), isScalar);
  for (const auto& kv : j.at("__map")) {
    if (!kv.is_array() || kv.size() != 2 || !isScalar(kv[1])) return false;
  }
  return true;
}

void emitScalar(YAML::Emitter& out, const Json& j) {
  if (j.is_null())
    out << YAML::Null;
  else if (j.is_boolean())
    out << (j.get<bool>() ? "true" : "false");
  else if (j.is_number())
    out << j.dump();  // shortest text that reads back as the same double
  else if (j.is_string())
    out << j.get<std::string>();
  else
    throw std::invalid_argument("unexpected JSON value " + jsonText(j).substr(0, 80));
}

void emit(YAML::Emitter& out, const Json& j, int depth) {
  if (depth > 64) throw std::invalid_argument("the document nests deeper than 64 levels");
  if (j.is_object()) {
    if (!j.contains("__map") || !j["__map"].is_array() || j.size() != 1)
      throw std::invalid_argument("a map must be {\"__map\": [[key, value], ...]}");
    // Short maps of scalars on one line ({x: 1, y: 2}), as the scenarios write them.
    const bool flow = depth > 0 && allScalars(j) && j["__map"].size() <= 8;
    if (flow) out << YAML::Flow;
    out << YAML::BeginMap;
    for (const auto& kv : j["__map"]) {
      if (!kv.is_array() || kv.size() != 2 || !kv[0].is_string())
        throw std::invalid_argument("a map entry must be [key, value] with a string key");
      out << YAML::Key << kv[0].get<std::string>() << YAML::Value;
      emit(out, kv[1], depth + 1);
    }
    out << YAML::EndMap;
  } else if (j.is_array()) {
    if (allScalars(j)) out << YAML::Flow;
    out << YAML::BeginSeq;
    for (const auto& item : j) emit(out, item, depth + 1);
    out << YAML::EndSeq;
  } else {
    emitScalar(out, j);
  }
}

bool hasDotDot(const fs::path& p) {
  for (const auto& part : p)
    if (part == "..") return true;
  return false;
}

bool within(const fs::path& root, const fs::path& p) {
  auto r = root.begin(), q = p.begin();
  for (; r != root.end(); ++r, ++q)
    if (q == p.end() || *r != *q) return false;
  return true;
}

// A temporary copy the loader read, and the file of the editor's folder it stands for.
struct StandIn {
  fs::path temp;
  std::string relative;
};

Json errorJson(const std::exception& e, const std::vector<StandIn>& stand_ins, const fs::path& root) {
  // Messages name the files the loader read: each temporary copy stands for the file being edited.
  std::string message = e.what();
  for (const auto& s : stand_ins)
    for (std::size_t at; (at = message.find(s.temp.string())) != std::string::npos;)
      message.replace(at, s.temp.string().size(), s.relative);
  const std::string root_prefix = root.string() + "/";
  for (std::size_t at; (at = message.find(root_prefix)) != std::string::npos;) message.erase(at, root_prefix.size());
  Json err = {{"message", message}};
  if (const auto* ce = dynamic_cast<const ConfigError*>(&e)) {
    std::string file = ce->file();
    for (const auto& s : stand_ins)
      if (file == s.temp.string()) file = s.relative;
    if (file.rfind(root_prefix, 0) == 0) file.erase(0, root_prefix.size());
    err["file"] = file;
    err["line"] = ce->line();
    err["key"] = ce->key();
  }
  return err;
}

// The `people:` value of a scenario document when it is a file name (an agents file), else null.
const Json* peopleFileName(const Json& doc) {
  if (!doc.is_object() || !doc.contains("__map") || !doc["__map"].is_array()) return nullptr;
  for (const auto& kv : doc["__map"])
    if (kv.is_array() && kv.size() == 2 && kv[0] == "people" && kv[1].is_string()) return &kv[1];
  return nullptr;
}

std::string readText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::atomic<unsigned> temp_counter{0};

// Creates a file of its own in `folder` (O_EXCL: no other request, thread or process shares its name),
// writes `text` into it and flushes it to disk; returns its path. Throws std::runtime_error.
fs::path writeNewFile(const fs::path& folder, const std::string& text) {
  for (int attempt = 0;; ++attempt) {
    const fs::path file =
        folder / (".hunav_view_" + std::to_string(::getpid()) + "_" + std::to_string(temp_counter++) + ".yaml.tmp");
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
      if (errno == EEXIST && attempt < 100) continue;
      throw std::runtime_error("cannot create a file in " + folder.string() + ": " + std::strerror(errno));
    }
    std::size_t written = 0;
    while (written < text.size()) {
      const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      written += static_cast<std::size_t>(n);
    }
    const bool ok = written == text.size() && ::fsync(fd) == 0;
    const int saved_errno = errno;
    if (::close(fd) != 0 || !ok) {
      ::unlink(file.c_str());
      throw std::runtime_error("cannot write " + file.string() + ": " + std::strerror(ok ? errno : saved_errno));
    }
    return file;
  }
}

// `target` whole or not at all: a file of its own beside it, flushed, renamed over it.
void writeWhole(const fs::path& target, const std::string& text) {
  const fs::path temp = writeNewFile(target.parent_path(), text);
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    fs::remove(temp, ec);
    throw std::runtime_error("cannot write " + target.string());
  }
}

}  // namespace

Json jsonFromYaml(const std::string& text) {
  try {
    return toJson(YAML::Load(text));
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument("line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

std::string yamlFromJson(const Json& doc) {
  YAML::Emitter out;
  out.SetIndent(2);
  emit(out, doc, 0);
  if (!out.good()) throw std::invalid_argument(std::string("cannot write YAML: ") + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

Editor::Editor(const fs::path& root) {
  std::error_code ec;
  root_ = fs::canonical(root, ec);
  if (ec || !fs::is_directory(root_)) throw ConfigError(root.string(), 0, "--editor", "not a folder that can be read");
}

fs::path Editor::resolve(const std::string& relative, bool must_exist) const {
  if (relative.empty()) throw PathError("empty path");
  if (relative.find('\0') != std::string::npos) throw PathError("a path must not contain NUL");
  const fs::path rel(relative);
  if (rel.is_absolute())
    throw PathError("'" + relative + "': absolute paths are refused (give a path inside " + root_.string() + ")");
  if (hasDotDot(rel)) throw PathError("'" + relative + "': '..' is refused (paths stay inside " + root_.string() + ")");
  // weakly_canonical follows every symlink of the part that exists: one that leads out is caught.
  std::error_code ec;
  const fs::path full = fs::weakly_canonical(root_ / rel, ec);
  if (ec) throw PathError("'" + relative + "': " + ec.message());
  if (!within(root_, full)) throw PathError("'" + relative + "': leads out of " + root_.string() + " (a symlink?)");
  if (must_exist && !fs::is_regular_file(full)) throw PathError("'" + relative + "': no such file");
  return full;
}

Json Editor::files() const {
  Json out = Json::array();
  std::error_code ec;
  fs::recursive_directory_iterator it(root_, fs::directory_options::skip_permission_denied, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    if (it.depth() > 4) {
      it.disable_recursion_pending();
      continue;
    }
    const auto& p = it->path();
    const auto ext = p.extension().string();
    if ((ext != ".yaml" && ext != ".yml") || !it->is_regular_file()) continue;
    const auto rel = p.lexically_relative(root_).string();
    try {
      resolve(rel, true);  // a symlink out of the root is not listed
    } catch (const PathError&) {
      continue;
    }
    out.push_back(rel);
  }
  std::vector<std::string> names = out.get<std::vector<std::string>>();
  std::sort(names.begin(), names.end());
  return names;
}

std::optional<std::string> Editor::agentsFileOf(const std::string& relative, const Json& doc) const {
  const Json* name = peopleFileName(doc);
  if (name == nullptr) return std::nullopt;
  const fs::path scenario = resolve(relative, false);
  const fs::path named(name->get<std::string>());
  if (named.empty()) throw PathError("people: an empty file name");
  // The loader resolves the agents file from the scenario's folder; it too must stay inside the root.
  std::error_code ec;
  const fs::path full = fs::weakly_canonical(named.is_absolute() ? named : scenario.parent_path() / named, ec);
  if (ec || !within(root_, full))
    throw PathError("people: '" + named.string() + "' lies outside " + root_.string() + " (edit it there)");
  return full.lexically_relative(root_).string();
}

Json Editor::open(const std::string& relative) const {
  const fs::path file = resolve(relative, true);
  Json out = {{"path", relative}, {"doc", nullptr}, {"people", nullptr}, {"scene", nullptr}, {"error", nullptr}};
  try {
    out["doc"] = jsonFromYaml(readText(file));
  } catch (const std::invalid_argument& e) {
    out["error"] = {{"message", relative + ": " + e.what()}, {"file", relative}};
    return out;
  }
  // People kept in an agents file travel with the scenario, to be edited and saved with it.
  try {
    if (auto agents = agentsFileOf(relative, out["doc"])) {
      const fs::path agents_file = resolve(*agents, true);
      out["people"] = {{"path", *agents}, {"doc", jsonFromYaml(readText(agents_file))}};
    }
  } catch (const std::exception& e) {
    out["people"] = {{"path", nullptr}, {"doc", nullptr}, {"error", e.what()}};
  }
  try {
    out["scene"] = sceneJson(loadScenario(file.string()));
  } catch (const std::exception& e) {
    out["error"] = errorJson(e, {{file, relative}}, root_);
  }
  return out;
}

fs::path Editor::resolveTarget(const std::string& relative) const {
  const fs::path target = resolve(relative, false);
  std::error_code ec;
  if (target == root_ || fs::is_directory(target, ec))
    throw PathError("'" + relative + "': a folder (give the name of a .yaml file)");
  const std::string ext = target.extension().string();
  if (ext != ".yaml" && ext != ".yml")
    throw PathError("'" + relative + "': the editor writes .yaml and .yml files only");
  // The loader reads files, and relative map / agent / tree paths resolve from the file's folder:
  // copies are checked beside the targets.
  if (!fs::is_directory(target.parent_path(), ec)) throw PathError("'" + relative + "': its folder does not exist");
  return target;
}

Json Editor::validate(const std::string& relative, const Json& doc, const Json& people_doc) const {
  const fs::path target = resolveTarget(relative);
  Json scenario_doc = doc;
  std::optional<std::string> agents;
  std::string people_yaml;
  if (!people_doc.is_null()) {
    agents = agentsFileOf(relative, doc);
    if (!agents)
      throw std::invalid_argument("an agents file document was sent, but the scenario's people: is no file name");
    people_yaml = yamlFromJson(people_doc);
    resolveTarget(*agents);
  }
  std::string yaml = yamlFromJson(scenario_doc);
  // Each copy is a file of its own (concurrent checks of one folder never share a name).
  std::vector<StandIn> stand_ins;
  Json result = {{"ok", false}, {"error", nullptr}, {"scene", nullptr}};
  try {
    if (agents) {
      const fs::path agents_temp = writeNewFile(resolve(*agents, false).parent_path(), people_yaml);
      stand_ins.push_back({agents_temp, *agents});
      // The copy of the scenario names the copy of the agents file, in the same folder as the original.
      const fs::path named(peopleFileName(doc)->get<std::string>());
      for (auto& kv : scenario_doc["__map"])
        if (kv[0] == "people") kv[1] = (named.parent_path() / agents_temp.filename()).string();
      yaml = yamlFromJson(scenario_doc);
    }
    stand_ins.push_back({writeNewFile(target.parent_path(), yaml), relative});
    Scenario s = loadScenario(stand_ins.back().temp.string());
    s.file = target.string();
    result["ok"] = true;
    result["scene"] = sceneJson(s);
  } catch (const std::exception& e) {
    result["error"] = errorJson(e, stand_ins, root_);
  }
  std::error_code ec;
  for (const auto& s : stand_ins) fs::remove(s.temp, ec);
  return result;
}

Json Editor::save(const std::string& relative, const Json& doc, const Json& people_doc) const {
  Json result = validate(relative, doc, people_doc);
  if (!result["ok"].get<bool>()) return result;
  // One save at a time: a scenario and its agents file are written as a pair.
  std::lock_guard<std::mutex> lock(writes_);
  if (!people_doc.is_null()) {
    const std::string agents = *agentsFileOf(relative, doc);
    writeWhole(resolveTarget(agents), yamlFromJson(people_doc));
    result["people_path"] = agents;
  }
  writeWhole(resolveTarget(relative), yamlFromJson(doc));
  result["path"] = relative;
  return result;
}

Json Editor::run(const std::string& relative, const std::string& planner, double duration) const {
  const fs::path file = resolve(relative, true);
  // A planner name is one of the registered ones: it also names the run's folder.
  if (planner != "none" && !planners::hasPlanner(planner))
    throw std::invalid_argument("unknown planner '" + planner.substr(0, 64) + "'");
  if (!(duration >= 0.0)) throw std::invalid_argument("duration must be a number >= 0");
  Json result = {{"ok", false}, {"error", nullptr}};
  try {
    Scenario s = loadScenario(file.string());
    if (duration > 0.0) {
      checkDurationOverride(duration);
      s.time_limit = duration;
    }
    // The folder inside the root, whatever the scenario's name: (and a symlinked view_runs) says.
    const fs::path out = resolve(
        "view_runs/" + results::safeFileName(s.name.empty() ? file.stem().string() : s.name) + "_" + planner, false);
    fs::create_directories(out);
    runner::RunOptions options;
    options.planner = planner;
    options.out_dir = out.string();
    const auto outcome = runner::runInProcess(s, options);
    result["ok"] = true;
    result["out_dir"] = out.lexically_relative(root_).string();
    result["status"] = outcome.episode.status;
    result["fingerprint"] = outcome.episode.fingerprint;
    result["sim_time"] = outcome.episode.sim_time;
  } catch (const std::exception& e) {
    result["error"] = errorJson(e, {{file, relative}}, root_);
  }
  return result;
}

}  // namespace hunav::view
