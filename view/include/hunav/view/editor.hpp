#pragma once
// The scenario editor's server side. Every file it reads or writes lies inside one folder (the root,
// the folder hunav_view was started on): a path with "..", an absolute path, or one that a symlink
// leads out of the root is refused (PathError). A scenario travels to the page as its YAML tree in
// JSON (maps keep their key order, scalars are strings), so the page edits the document itself and
// saving writes back every key the user did not touch; the project's own loader (loadScenario)
// validates every version before it is saved, and its "file:line: key: what" is sent back.
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>

#include "hunav/view/frames.hpp"

namespace hunav::view {

struct PathError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The YAML text of a document tree as the page sends it (see above); throws std::invalid_argument.
std::string yamlFromJson(const Json& doc);
// The tree of a YAML text (throws std::invalid_argument with the line of a syntax error).
Json jsonFromYaml(const std::string& text);

class Editor {
 public:
  // `root` must be an existing folder. Runs started from the page write into root/view_runs/.
  explicit Editor(const std::filesystem::path& root);

  const std::filesystem::path& root() const { return root_; }
  // The file `relative` names inside the root. Throws PathError: empty, absolute, "..", a NUL, a
  // name that leaves the root through a symlink, or (must_exist) no such regular file.
  std::filesystem::path resolve(const std::string& relative, bool must_exist) const;

  // Scenario files (.yaml/.yml) under the root, relative, sorted (not following symlinks out of it).
  Json files() const;
  // {path, doc, people, scene | null, error | null}: the tree of the file and, when it loads, its
  // scene. When its `people:` names an agents file, people is {path, doc} of that file (relative to
  // the root), or {error} when it lies outside the root.
  Json open(const std::string& relative) const;
  // {ok, error: {message, file, line, key, what} | null, scene | null}: `doc` as it would be saved at
  // `relative` (relative map and agent files resolve from that folder), checked by loadScenario.
  // `people_doc` (or null): the edited tree of the agents file the scenario's `people:` names.
  Json validate(const std::string& relative, const Json& doc, const Json& people_doc = nullptr) const;
  // validate(), then, when it loads, writes the agents file (if given) and the scenario's YAML to
  // `relative` (a new or existing .yaml/.yml file), each whole or not at all: a temporary file of its
  // own in the target's folder, flushed to disk, renamed over the target. Saves run one at a time.
  // validate() and save() refuse (PathError) a target that is the root, a folder, not .yaml/.yml, or
  // in a folder that does not exist.
  Json save(const std::string& relative, const Json& doc, const Json& people_doc = nullptr) const;
  // Runs the saved scenario at `relative` in this process (runner::runInProcess, planner `planner`),
  // results into root/view_runs/<name>_<planner> (confined to the root like every path);
  // returns {ok, out_dir (relative), status, fingerprint, error}. Throws std::invalid_argument for a
  // planner that is not registered (nor "none") and a negative or non-numeric duration.
  Json run(const std::string& relative, const std::string& planner, double duration) const;

 private:
  // The agents file (relative to the root) the scenario document's `people:` names, if it names one;
  // PathError when it lies outside the root.
  std::optional<std::string> agentsFileOf(const std::string& relative, const Json& doc) const;
  // resolve(relative, false) for a file the editor writes: a .yaml or .yml file (not the root, not a
  // folder) in an existing folder of the root; PathError otherwise.
  std::filesystem::path resolveTarget(const std::string& relative) const;

  std::filesystem::path root_;
  mutable std::mutex writes_;  // saves one at a time (a scenario and its agents file as a pair)
};

}  // namespace hunav::view
