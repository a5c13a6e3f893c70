#include "hunav/realism/tracks.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <set>
#include <sstream>

#include "hunav/config_error.hpp"

namespace hunav::realism {

namespace {

struct Row {
  int line;
  std::int64_t frame;
  int id;
  Vec2 p;
};

double parseNumber(const std::string& text, const std::string& path, int line, const char* key) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    throw ConfigError(path, line, key, "expected a finite number, got '" + text + "'");
  return v;
}

std::int64_t parseInteger(const std::string& text, const std::string& path, int line, const char* key) {
  const double v = parseNumber(text, path, line, key);
  // Frames and ids are written as floats ("780", "10.0"); anything with a fraction is not one.
  if (v != std::floor(v) || std::fabs(v) > 1e15)
    throw ConfigError(path, line, key, "expected an integer, got '" + text + "'");
  return static_cast<std::int64_t>(v);
}

}  // namespace

std::string datasetName(const std::string& path) {
  const std::string stem = std::filesystem::path(path).stem().string();
  if (stem == "biwi_eth") return "ETH";
  if (stem == "biwi_hotel") return "Hotel";
  if (stem == "crowds_zara01") return "Zara1";
  if (stem == "crowds_zara02") return "Zara2";
  if (stem == "students003") return "Univ";
  return stem;
}

double defaultFrameInterval(const std::string& path) {
  return std::filesystem::path(path).stem().string() == "biwi_eth" ? 1.0 / 1.5 : 0.4;
}

Dataset readTracks(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path, 0, "", "cannot open the track file");
  std::vector<Row> rows;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::istringstream fields(text);
    std::vector<std::string> f;
    for (std::string w; fields >> w;) f.push_back(w);
    if (f.empty()) continue;  // blank lines carry nothing
    if (f.size() != 4)
      throw ConfigError(path, line, "row", "expected 4 fields 'frame id x y', got " + std::to_string(f.size()));
    Row r;
    r.line = line;
    r.frame = parseInteger(f[0], path, line, "frame");
    // The files list frames in time order; a frame that goes back is a file put together wrongly.
    if (!rows.empty() && r.frame < rows.back().frame)
      throw ConfigError(path, line, "frame",
                        "frame " + f[0] + " comes after frame " + std::to_string(rows.back().frame) +
                            ": frames must not decrease from one row to the next");
    const std::int64_t id = parseInteger(f[1], path, line, "id");
    if (id < 0 || id > 1'000'000'000) throw ConfigError(path, line, "id", "expected an id in [0, 1e9], got " + f[1]);
    r.id = static_cast<int>(id);
    r.p = Vec2(parseNumber(f[2], path, line, "x"), parseNumber(f[3], path, line, "y"));
    rows.push_back(r);
  }
  if (rows.empty()) throw ConfigError(path, line, "", "no track rows (expected lines 'frame id x y')");

  std::set<std::int64_t> numbers;
  for (const Row& r : rows) numbers.insert(r.frame);
  std::int64_t step = 0;
  for (auto it = std::next(numbers.begin()); it != numbers.end(); ++it)
    step = step == 0 ? *it - *std::prev(it) : std::min(step, *it - *std::prev(it));
  if (step == 0) step = 1;  // a single frame: any step

  Dataset d;
  d.path = path;
  d.name = datasetName(path);
  d.frame_interval = defaultFrameInterval(path);
  d.frame_step = step;
  std::set<int> ids;
  for (const Row& r : rows) {
    // Frame indices count steps from the first frame; a frame off that grid has no place in time.
    const std::int64_t first = *numbers.begin();
    if ((r.frame - first) % step != 0)
      throw ConfigError(path, r.line, "frame",
                        "frame " + std::to_string(r.frame) + " is not on the file's grid of frames " +
                            std::to_string(first) + " + k * " + std::to_string(step));
    auto& people = d.frames[(r.frame - first) / step];
    if (!people.emplace(r.id, r.p).second)
      throw ConfigError(path, r.line, "id",
                        "person " + std::to_string(r.id) + " appears twice in frame " + std::to_string(r.frame));
    ids.insert(r.id);
  }
  d.rows = rows.size();
  d.people = ids.size();
  return d;
}

}  // namespace hunav::realism
