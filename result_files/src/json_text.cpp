#include "hunav/results/json_text.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "hunav/config_error.hpp"
#include "hunav/results/atomic_file.hpp"

namespace hunav::results {

namespace fs = std::filesystem;

void writeJsonFile(const fs::path& file, const nlohmann::ordered_json& json, int indent) {
  writeFileAtomically(
      file, json.dump(indent, ' ', /*ensure_ascii=*/false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
}

namespace {

// Deeper documents are refused before they are built: no result file nests more than a few levels.
constexpr int kMaxDepth = 256;

// An iterator over the text that counts the line breaks it moved past, so that the parser's
// callback knows the line of the key it was just given (nlohmann keeps no positions).
class LineCountingIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  LineCountingIterator(const char* p, int* line) : p_(p), line_(line) {}
  reference operator*() const { return *p_; }
  LineCountingIterator& operator++() {
    if (*p_ == '\n') ++*line_;
    ++p_;
    return *this;
  }
  LineCountingIterator operator++(int) {
    LineCountingIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const LineCountingIterator& o) const { return p_ == o.p_; }
  bool operator!=(const LineCountingIterator& o) const { return p_ != o.p_; }

 private:
  const char* p_;
  int* line_;
};

// The path of the value being parsed: one entry per open object or array.
struct PathFrame {
  bool array = false;
  std::size_t next_index = 0;
  std::string part;  // "key" or "[index]" of the current member
};

std::string pathOf(const std::vector<PathFrame>& frames) {
  std::string path;
  for (const PathFrame& f : frames) {
    if (f.part.empty()) break;
    if (!path.empty() && !f.array) path += '.';
    path += f.part;
  }
  return path;
}

// A value quoted in a message: a string as 'text', anything else as JSON.
std::string shown(const nlohmann::ordered_json& v) {
  return v.is_string() ? "'" + v.get<std::string>() + "'" : v.dump();
}

int lineAt(const std::string& text, std::size_t byte) {
  const auto end = text.begin() + static_cast<std::ptrdiff_t>(std::min(byte, text.size()));
  return 1 + static_cast<int>(std::count(text.begin(), end, '\n'));
}

}  // namespace

JsonDocument JsonDocument::read(const fs::path& file) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw ConfigError(file.string(), 0, "", "missing file");
  if (!fs::is_regular_file(file, ec)) throw ConfigError(file.string(), 0, "", "not a regular file");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ConfigError(file.string(), 0, "", "cannot read the file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse(buffer.str(), file.string());
}

JsonDocument JsonDocument::parse(const std::string& text, const std::string& name) {
  JsonDocument doc;
  doc.file_ = name;
  int line = 1;
  std::vector<PathFrame> frames;
  // An element of an array gets its index when it starts.
  auto element = [&frames, &doc, &line] {
    if (frames.empty() || !frames.back().array) return;
    frames.back().part = "[" + std::to_string(frames.back().next_index++) + "]";
    doc.lines_.emplace(pathOf(frames), line);
  };
  const nlohmann::ordered_json::parser_callback_t callback = [&](int depth, nlohmann::ordered_json::parse_event_t event,
                                                                 nlohmann::ordered_json& parsed) {
    using E = nlohmann::ordered_json::parse_event_t;
    if (depth > kMaxDepth)
      throw ConfigError(name, line, pathOf(frames), "nests deeper than " + std::to_string(kMaxDepth) + " levels");
    switch (event) {
      case E::object_start:
      case E::array_start:
        element();
        frames.push_back({event == E::array_start, 0, ""});
        break;
      case E::object_end:
      case E::array_end:
        if (!frames.empty()) frames.pop_back();
        break;
      case E::key:
        // The iterator is just past the key's closing quote: `line` is the key's.
        if (!frames.empty()) frames.back().part = parsed.get<std::string>();
        doc.lines_.emplace(pathOf(frames), line);
        break;
      case E::value:
        element();
        break;
    }
    return true;
  };
  const LineCountingIterator begin(text.data(), &line);
  const LineCountingIterator end(text.data() + text.size(), &line);
  try {
    doc.root_ = nlohmann::ordered_json::parse(begin, end, callback);
  } catch (const nlohmann::ordered_json::parse_error& e) {
    // e.what() is "[json.exception.parse_error.101] parse error at line L, column C: ...".
    std::string what = e.what();
    if (const auto colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
    throw ConfigError(name, lineAt(text, e.byte == 0 ? 0 : e.byte - 1), "", "not valid JSON: " + what);
  } catch (const nlohmann::ordered_json::exception& e) {
    // A number beyond a double ("sim_time": 1e400, out_of_range.406): the line of its key (the parser
    // stopped past the number).
    std::string what = e.what();
    if (const auto bracket = what.find("] "); bracket != std::string::npos) what = what.substr(bracket + 2);
    const std::string key = pathOf(frames);
    const auto at = doc.lines_.find(key);
    throw ConfigError(name, at != doc.lines_.end() ? at->second : line, key, what);
  }
  return doc;
}

int JsonDocument::lineOf(const std::string& path) const {
  const auto it = lines_.find(path);
  return it == lines_.end() ? 0 : it->second;
}

void JsonDocument::fail(const std::string& path, const std::string& what) const {
  // A key the file lacks is named with the line of the closest enclosing key or element it has.
  std::string at = path;
  int line = lineOf(at);
  while (line == 0 && !at.empty()) {
    const std::size_t cut = at.find_last_of(".[");
    at.resize(cut == std::string::npos ? 0 : cut);
    line = lineOf(at);
  }
  throw ConfigError(file_, line, path, what);
}

std::string JsonDocument::join(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
}

std::string JsonDocument::element(const std::string& where, std::size_t index) {
  return where + "[" + std::to_string(index) + "]";
}

const nlohmann::ordered_json* JsonDocument::find(const nlohmann::ordered_json& object, const std::string& where,
                                                 const char* key) const {
  if (!object.is_object()) fail(where, "expected an object");
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

std::string JsonDocument::text(const nlohmann::ordered_json& object, const std::string& where, const char* key,
                               const std::string& fallback) const {
  const nlohmann::ordered_json* v = find(object, where, key);
  if (v == nullptr) return fallback;
  if (!v->is_string()) fail(join(where, key), "expected a string, got " + shown(*v));
  return v->get<std::string>();
}

std::int64_t JsonDocument::integer(const nlohmann::ordered_json& object, const std::string& where, const char* key,
                                   std::int64_t fallback) const {
  const nlohmann::ordered_json* v = find(object, where, key);
  if (v == nullptr) return fallback;
  if (v->is_number_integer() &&
      (!v->is_number_unsigned() ||
       v->get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())))
    return v->get<std::int64_t>();
  fail(join(where, key), "expected an integer, got " + shown(*v));
}

double JsonDocument::number(const nlohmann::ordered_json& object, const std::string& where, const char* key,
                            double fallback) const {
  const nlohmann::ordered_json* v = find(object, where, key);
  if (v == nullptr) return fallback;
  if (!v->is_number()) fail(join(where, key), "expected a number, got " + shown(*v));
  return v->get<double>();
}

bool JsonDocument::boolean(const nlohmann::ordered_json& object, const std::string& where, const char* key,
                           bool fallback) const {
  const nlohmann::ordered_json* v = find(object, where, key);
  if (v == nullptr) return fallback;
  if (!v->is_boolean()) fail(join(where, key), "expected true or false, got " + shown(*v));
  return v->get<bool>();
}

}  // namespace hunav::results
