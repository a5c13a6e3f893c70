#pragma once
// JSON text of the result files, read and written with nlohmann-json: files written atomically
// (run.json), and JSON files read with every problem reported as a ConfigError naming file, line and
// key (run.json, expect.json). Objects keep the order of the file (nlohmann::ordered_json).
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace hunav::results {

// Writes `json` to `file` as nlohmann's dump with `indent` spaces (-1: one line) and a final line
// break, atomically (temporary file + rename). Strings that are not valid UTF-8 have their bad bytes
// replaced by U+FFFD rather than throwing. Throws std::runtime_error on I/O errors.
void writeJsonFile(const std::filesystem::path& file, const nlohmann::ordered_json& json, int indent);

// A JSON file parsed with nlohmann-json, which remembers the line of every key so that errors about
// a value name the line it is on. Keys are named by their path: "seed", "metrics.completed",
// "conditions[0].pass".
class JsonDocument {
 public:
  // Throws ConfigError: file missing or unreadable, or not JSON (with the line of the problem, also
  // for a number beyond a double such as 1e400, and for arrays and objects nested deeper than 256).
  static JsonDocument read(const std::filesystem::path& file);
  // The same from text; `name` is the file name used in messages.
  static JsonDocument parse(const std::string& text, const std::string& name);

  const nlohmann::ordered_json& root() const { return root_; }
  const std::string& file() const { return file_; }
  // The line of the key at `path` (1-based), 0 when the file has no such key.
  int lineOf(const std::string& path) const;
  // Throws ConfigError(file, line, path, what): the line of `path`, or for a key the file lacks, of
  // the closest enclosing key or array element it has.
  [[noreturn]] void fail(const std::string& path, const std::string& what) const;

  // The value of `key` in `object` (at `where`, the object's path, "" for the root) as a string,
  // integer, number or boolean; `fallback` when the key is absent. A value of another type throws
  // ConfigError naming its line and path.
  std::string text(const nlohmann::ordered_json& object, const std::string& where, const char* key,
                   const std::string& fallback) const;
  std::int64_t integer(const nlohmann::ordered_json& object, const std::string& where, const char* key,
                       std::int64_t fallback) const;
  double number(const nlohmann::ordered_json& object, const std::string& where, const char* key, double fallback) const;
  bool boolean(const nlohmann::ordered_json& object, const std::string& where, const char* key, bool fallback) const;

  // "where.key" ("key" at the root); "where[index]".
  static std::string join(const std::string& where, const std::string& key);
  static std::string element(const std::string& where, std::size_t index);

 private:
  const nlohmann::ordered_json* find(const nlohmann::ordered_json& object, const std::string& where,
                                     const char* key) const;

  std::string file_;
  nlohmann::ordered_json root_;
  std::map<std::string, int> lines_;  // key path -> line
};

}  // namespace hunav::results
