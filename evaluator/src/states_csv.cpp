#include "hunav/evaluator/states_csv.hpp"

#include "hunav/config_error.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string_view>
#include <stdexcept>
#include <vector>

namespace hunav::evaluator {

namespace fs = std::filesystem;

namespace {
constexpr std::size_t kColumns = 19;
const std::array<const char*, kColumns> kColumnNames{
    "t",           "kind",          "id",     "x",     "y",     "yaw",    "vx",          "vy",  "vyaw", "linear_vel",
    "angular_vel", "radius",        "behavior", "behavior_state", "group", "goal_x", "goal_y", "goal_radius", "obs"};
enum Column : std::size_t {
  kT, kKind, kId, kX, kY, kYaw, kVx, kVy, kVyaw, kLinearVel, kAngularVel, kRadius,
  kBehavior, kBehaviorState, kGroup, kGoalX, kGoalY, kGoalRadius, kObs
};
}  // namespace

// ---------------------------------------------------------------------------------------------
// Writer

StatesCsvWriter::StatesCsvWriter(const fs::path& file) : path_(file) {
  file_ = std::fopen(file.c_str(), "w");
  if (file_ == nullptr)
    throw std::runtime_error(file.string() + ": cannot create: " + std::strerror(errno));
  if (std::fputs(kStatesCsvHeader, file_) == EOF || std::fputc('\n', file_) == EOF || std::fflush(file_) != 0)
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
}

StatesCsvWriter::~StatesCsvWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

void StatesCsvWriter::appendRow(const Recording& r, double t, const char* kind, const EntityState& e) {
  auto out = std::back_inserter(buffer_);
  fmt::format_to(out, FMT_COMPILE("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},"), t, kind, e.id, e.x, e.y, e.yaw, e.vx, e.vy,
                 e.vyaw, e.linear_vel, e.angular_vel, e.radius, static_cast<int>(e.behavior),
                 static_cast<int>(e.behavior_state), e.group);
  if (e.has_goal)
    fmt::format_to(out, FMT_COMPILE("{},{},{},"), e.goal_x, e.goal_y, e.goal_radius);
  else
    fmt::format_to(out, ",,,");
  bool first = true;
  for (const Vec2& p : r.obstacles(e)) {
    fmt::format_to(out, FMT_COMPILE("{}{}:{}"), first ? "" : ";", p.x(), p.y());
    first = false;
  }
  buffer_.push_back('\n');
}

void StatesCsvWriter::write(const Recording& r, const Sample& s) {
  if (file_ == nullptr) throw std::logic_error(path_.string() + ": written after close");
  buffer_.clear();
  appendRow(r, s.t, "robot", s.robot);
  for (const auto& a : r.agents(s)) appendRow(r, s.t, "agent", a);
  if (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size() || std::fflush(file_) != 0)
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
}

void StatesCsvWriter::close() {
  if (file_ == nullptr) return;
  const int status = std::fclose(file_);
  file_ = nullptr;
  if (status != 0) throw std::runtime_error(path_.string() + ": cannot close: " + std::strerror(errno));
}

// ---------------------------------------------------------------------------------------------
// Reader

namespace {

// A row split into views of the line (no allocation per field).
class RowParser {
 public:
  using Fields = std::array<std::string_view, kColumns>;
  RowParser(const fs::path& file, int line, const Fields& fields) : file_(file), line_(line), fields_(fields) {}

  [[noreturn]] void fail(std::size_t column, const std::string& what) const {
    throw ConfigError(file_.string(), line_, kColumnNames[column], what);
  }
  std::string_view text(std::size_t column) const { return fields_[column]; }

  double real(std::size_t column) const {
    const std::string_view s = fields_[column];
    double v = 0.0;
    if (!parseReal(s, v)) fail(column, "expected a finite number, got '" + std::string(s) + "'");
    return v;
  }

  template <class Int>
  Int integer(std::size_t column) const {
    const std::string_view s = fields_[column];
    long long v = 0;
    const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || res.ec != std::errc() || res.ptr != s.data() + s.size() ||
        v < static_cast<long long>(std::numeric_limits<Int>::min()) ||
        v > static_cast<long long>(std::numeric_limits<Int>::max()))
      fail(column, "expected an integer, got '" + std::string(s) + "'");
    return static_cast<Int>(v);
  }

  static bool parseReal(std::string_view s, double& v) {
    const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    return !s.empty() && res.ec == std::errc() && res.ptr == s.data() + s.size() && std::isfinite(v);
  }

  // "x:y;x:y" or empty, appended to `points` (cleared first).
  void obstacles(std::vector<Vec2>& points) const {
    points.clear();
    const std::string_view s = fields_[kObs];
    if (s.empty()) return;
    std::size_t start = 0;
    while (true) {
      const std::size_t end = std::min(s.find(';', start), s.size());
      const std::string_view item = s.substr(start, end - start);
      const std::size_t colon = item.find(':');
      double x = 0.0;
      double y = 0.0;
      if (colon == std::string_view::npos || !parseReal(item.substr(0, colon), x) || !parseReal(item.substr(colon + 1), y))
        fail(kObs, "expected points as x:y;x:y, got '" + std::string(item) + "'");
      points.emplace_back(x, y);
      if (end == s.size()) break;
      start = end + 1;
    }
  }

 private:
  const fs::path& file_;
  int line_;
  const Fields& fields_;
};

// Splits at commas into `fields`; returns the number of fields found (counting past kColumns).
std::size_t splitCsvLine(std::string_view line, RowParser::Fields& fields) {
  std::size_t n = 0;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string_view f = line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    if (n < kColumns) fields[n] = f;
    ++n;
    if (comma == std::string_view::npos) return n;
    start = comma + 1;
  }
}

}  // namespace

Recording readStatesCsv(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw ConfigError(file.string(), 0, "", "cannot open the file");

  std::string line;
  if (!std::getline(in, line)) throw ConfigError(file.string(), 1, "header", "the file is empty");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != kStatesCsvHeader)
    throw ConfigError(file.string(), 1, "header", "expected '" + std::string(kStatesCsvHeader) + "'");

  Recording rec;
  bool have_robot = false;  // a sample is being assembled
  double sample_t = 0.0;
  EntityState robot;
  std::vector<EntityState> agents;
  std::vector<Vec2> obs;
  RowParser::Fields fields;
  auto commit = [&] {
    if (have_robot) rec.addSample(sample_t, robot, agents);
    agents.clear();
  };

  // After the first rows, reserve for the whole file from the bytes per row seen so far (2 % spare):
  // growing vectors by doubling would hold two copies of a long recording at once.
  std::error_code size_error;
  const auto file_size = fs::file_size(file, size_error);
  std::uintmax_t bytes_read = line.size() + 1;
  constexpr int kEstimateAfter = 4096;

  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    bytes_read += line.size() + 1;
    if (line_no == kEstimateAfter && !size_error && !rec.empty()) {
      const double scale = 1.02 * static_cast<double>(file_size) / static_cast<double>(bytes_read);
      rec.reserve(static_cast<std::size_t>(scale * static_cast<double>(rec.size() + 1)),
                  static_cast<std::size_t>(scale * static_cast<double>(rec.agentRows() + agents.size())),
                  static_cast<std::size_t>(scale * static_cast<double>(rec.obstaclePoints())));
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::size_t count = splitCsvLine(line, fields);
    if (count != kColumns)
      throw ConfigError(file.string(), line_no, "row", fmt::format("expected {} fields, got {}", kColumns, count));
    const RowParser row(file, line_no, fields);

    EntityState e;
    const double t = row.real(kT);
    const std::string_view kind = row.text(kKind);
    if (kind != "robot" && kind != "agent") row.fail(kKind, "expected robot or agent, got '" + std::string(kind) + "'");
    e.id = row.integer<std::int32_t>(kId);
    e.x = row.real(kX);
    e.y = row.real(kY);
    e.yaw = row.real(kYaw);
    e.vx = row.real(kVx);
    e.vy = row.real(kVy);
    e.vyaw = row.real(kVyaw);
    e.linear_vel = row.real(kLinearVel);
    e.angular_vel = row.real(kAngularVel);
    e.radius = row.real(kRadius);
    e.behavior = row.integer<std::int8_t>(kBehavior);
    e.behavior_state = row.integer<std::int8_t>(kBehaviorState);
    e.group = row.integer<std::int32_t>(kGroup);
    const bool goal_empty =
        row.text(kGoalX).empty() && row.text(kGoalY).empty() && row.text(kGoalRadius).empty();
    if (!goal_empty) {
      e.has_goal = true;
      e.goal_x = row.real(kGoalX);
      e.goal_y = row.real(kGoalY);
      e.goal_radius = row.real(kGoalRadius);
    }
    row.obstacles(obs);
    e.obstacles_begin = rec.addObstacles(obs);
    e.obstacles_count = static_cast<std::uint32_t>(obs.size());

    if (kind == "robot") {
      commit();
      if (!rec.empty() && !(t > rec.back().t))
        row.fail(kT, fmt::format("time {} s does not follow the previous tick's {} s", t, rec.back().t));
      have_robot = true;
      sample_t = t;
      robot = e;
    } else {
      if (!have_robot) row.fail(kKind, "agent row before the first robot row");
      if (t != sample_t) row.fail(kT, fmt::format("agent row at {} s inside the tick of {} s", t, sample_t));
      agents.push_back(e);
    }
  }
  if (in.bad()) throw ConfigError(file.string(), line_no, "", "read error");
  commit();
  return rec;
}

}  // namespace hunav::evaluator
