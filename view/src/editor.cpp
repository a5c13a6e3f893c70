#include "hunav/view/editor.hpp"

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <fstream>
#include <optional>
#include <sstream>

#include "hunav/config_error.hpp"
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
    throw std::invalid_argument("unexpected JSON value " + j.dump().substr(0, 80));
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

void writeText(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

void writeWhole(const fs::path& target, const std::string& text) {
  const fs::path temp = target.parent_path() / (".hunav_view_save_" + std::to_string(::getpid()) + ".yaml");
  writeText(temp, text);
  fs::rename(temp, target);  // whole or not at all
}

std::atomic<unsigned> temp_counter{0};

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

Json Editor::validate(const std::string& relative, const Json& doc, const Json& people_doc) const {
  const fs::path target = resolve(relative, false);
  // The loader reads files, and relative map / agent / tree paths resolve from the file's folder:
  // check copies written beside the targets.
  if (!fs::is_directory(target.parent_path())) throw PathError("'" + relative + "': its folder does not exist");
  auto tempBeside = [](const fs::path& f) {
    return f.parent_path() /
           (".hunav_view_" + std::to_string(::getpid()) + "_" + std::to_string(temp_counter++) + ".yaml");
  };
  std::vector<StandIn> stand_ins;
  Json scenario_doc = doc;
  std::string people_yaml;
  if (!people_doc.is_null()) {
    const auto agents = agentsFileOf(relative, doc);
    if (!agents)
      throw std::invalid_argument("an agents file document was sent, but the scenario's people: is no file name");
    people_yaml = yamlFromJson(people_doc);
    const fs::path agents_target = resolve(*agents, false);
    const fs::path agents_temp = tempBeside(agents_target);
    stand_ins.push_back({agents_temp, *agents});
    // The copy of the scenario names the copy of the agents file, in the same folder as the original.
    const fs::path named(peopleFileName(doc)->get<std::string>());
    for (auto& kv : scenario_doc["__map"])
      if (kv[0] == "people") kv[1] = (named.parent_path() / agents_temp.filename()).string();
  }
  const std::string yaml = yamlFromJson(scenario_doc);
  stand_ins.push_back({tempBeside(target), relative});
  Json result = {{"ok", false}, {"error", nullptr}, {"scene", nullptr}};
  try {
    if (stand_ins.size() == 2) writeText(stand_ins[0].temp, people_yaml);
    writeText(stand_ins.back().temp, yaml);
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
  if (!people_doc.is_null()) {
    const std::string agents = *agentsFileOf(relative, doc);
    writeWhole(resolve(agents, false), yamlFromJson(people_doc));
    result["people_path"] = agents;
  }
  writeWhole(resolve(relative, false), yamlFromJson(doc));
  result["path"] = relative;
  return result;
}

Json Editor::run(const std::string& relative, const std::string& planner, double duration) const {
  const fs::path file = resolve(relative, true);
  Json result = {{"ok", false}, {"error", nullptr}};
  try {
    Scenario s = loadScenario(file.string());
    if (duration > 0.0) {
      checkDurationOverride(duration);
      s.time_limit = duration;
    }
    std::string name = s.name.empty() ? file.stem().string() : s.name;
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '_';
    const fs::path out = root_ / "view_runs" / (name + "_" + planner);
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
