#include "hunav/results/states_csv.hpp"

#include <fcntl.h>
#include <fmt/compile.h>
#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "hunav/bounds.hpp"
#include "hunav/config_error.hpp"

namespace hunav::results {

namespace fs = std::filesystem;

namespace {

// Numbers of a row lie within +-kMaxNumber (and are finite): beyond it the metrics' squared
// distances and sums could overflow to infinity, and the episode would be lost. Positions and speeds
// of live runs stay within +-1e6 (hunav::kMaxMagnitude); t may be larger.
constexpr double kMaxNumber = 1e9;
constexpr std::size_t kColumns = 19;
const std::array<const char*, kColumns> kColumnNames{
    "t",     "kind",   "id",         "x",           "y",      "yaw",      "vx",
    "vy",    "vyaw",   "linear_vel", "angular_vel", "radius", "behavior", "behavior_state",
    "group", "goal_x", "goal_y",     "goal_radius", "obs"};
enum Field : std::size_t {
  kT,
  kKind,
  kId,
  kX,
  kY,
  kYaw,
  kVx,
  kVy,
  kVyaw,
  kLinearVel,
  kAngularVel,
  kRadius,
  kBehavior,
  kBehaviorState,
  kGroup,
  kGoalX,
  kGoalY,
  kGoalRadius,
  kObs
};
}  // namespace

// ---------------------------------------------------------------------------------------------
// Writer

StatesCsvWriter::StatesCsvWriter(const fs::path& file) : path_(file) {
  file_ = std::fopen(file.c_str(), "w");
  if (file_ == nullptr) throw std::runtime_error(file.string() + ": cannot create: " + std::strerror(errno));
  if (std::fputs(kStatesCsvHeader, file_) == EOF || std::fputc('\n', file_) == EOF || std::fflush(file_) != 0)
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
}

StatesCsvWriter::~StatesCsvWriter() {
  if (file_ == nullptr) return;
  if (buffer_.size() > 0) std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
  std::fclose(file_);
}

namespace {
std::uint64_t bitsOf(double v) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  return bits;
}
}  // namespace

StatesCsvWriter::RowCache* StatesCsvWriter::agentCache(std::int32_t id) {
  if (id < 0 || id >= kCachedIds) return nullptr;
  const auto index = static_cast<std::size_t>(id);
  if (index >= agent_caches_.size()) agent_caches_.resize(index + 1);
  return &agent_caches_[index];
}

void StatesCsvWriter::appendRow(const Recording& r, const char* kind, const EntityState& e, RowCache* cache) {
  // The text of fmt "{}" for every field (NumberText for the doubles).
  auto integer = [this](long long v) {
    const fmt::format_int digits(v);
    buffer_.append(digits.data(), digits.data() + digits.size());
  };
  auto real = [this](double v) {
    numbers_.append(buffer_, v);
    buffer_.push_back(',');
  };
  auto appendText = [this](const std::string& text) { buffer_.append(text.data(), text.data() + text.size()); };
  // The text buffer_ received since `at`.
  auto textSince = [this](std::size_t at, std::string& into) { into.assign(buffer_.data() + at, buffer_.size() - at); };
  buffer_.append(time_text_.data(), time_text_.data() + time_text_.size());
  if (cache != nullptr && cache->has_head && cache->id == e.id) {
    appendText(cache->head);
  } else {
    const std::size_t at = buffer_.size();
    buffer_.push_back(',');
    buffer_.append(std::string_view(kind));
    buffer_.push_back(',');
    integer(e.id);
    buffer_.push_back(',');
    if (cache != nullptr) {
      textSince(at, cache->head);
      cache->has_head = true;
      cache->id = e.id;
    }
  }
  for (const double v : {e.x, e.y, e.yaw, e.vx, e.vy, e.vyaw, e.linear_vel, e.angular_vel}) real(v);
  const std::uint64_t radius = bitsOf(e.radius);
  const std::uint64_t goal_x = e.has_goal ? bitsOf(e.goal_x) : 0;
  const std::uint64_t goal_y = e.has_goal ? bitsOf(e.goal_y) : 0;
  const std::uint64_t goal_radius = e.has_goal ? bitsOf(e.goal_radius) : 0;
  if (cache != nullptr && cache->has_tail && cache->radius == radius && cache->behavior == e.behavior &&
      cache->behavior_state == e.behavior_state && cache->group == e.group && cache->has_goal == e.has_goal &&
      cache->goal_x == goal_x && cache->goal_y == goal_y && cache->goal_radius == goal_radius) {
    appendText(cache->tail);
  } else {
    const std::size_t at = buffer_.size();
    real(e.radius);
    integer(e.behavior);
    buffer_.push_back(',');
    integer(e.behavior_state);
    buffer_.push_back(',');
    integer(e.group);
    buffer_.push_back(',');
    if (e.has_goal) {
      real(e.goal_x);
      real(e.goal_y);
      real(e.goal_radius);
    } else {
      buffer_.append(std::string_view(",,,"));
    }
    if (cache != nullptr) {
      textSince(at, cache->tail);
      cache->has_tail = true;
      cache->radius = radius;
      cache->behavior = e.behavior;
      cache->behavior_state = e.behavior_state;
      cache->group = e.group;
      cache->has_goal = e.has_goal;
      cache->goal_x = goal_x;
      cache->goal_y = goal_y;
      cache->goal_radius = goal_radius;
    }
  }
  bool first = true;
  for (const Vec2& p : r.obstacles(e)) {
    if (!first) buffer_.push_back(';');
    numbers_.append(buffer_, p.x());
    buffer_.push_back(':');
    numbers_.append(buffer_, p.y());
    first = false;
  }
  buffer_.push_back('\n');
}

void StatesCsvWriter::write(const Recording& r, const Sample& s) {
  if (file_ == nullptr) throw std::logic_error(path_.string() + ": written after close");
  time_text_.clear();
  numbers_.append(time_text_, s.t);
  appendRow(r, "robot", s.robot, &robot_cache_);
  for (const auto& a : r.agents(s)) appendRow(r, "agent", a, agentCache(a.id));
  ++buffered_ticks_;
}

void StatesCsvWriter::flush() {
  if (file_ == nullptr) return;
  if (buffer_.size() > 0 &&
      (std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size() || std::fflush(file_) != 0))
    throw std::runtime_error(path_.string() + ": cannot write: " + std::strerror(errno));
  buffer_.clear();
  buffered_ticks_ = 0;
}

void StatesCsvWriter::close() {
  if (file_ == nullptr) return;
  std::exception_ptr error;
  try {
    flush();
  } catch (const std::exception&) {
    error = std::current_exception();
  }
  const int status = std::fclose(file_);
  file_ = nullptr;
  buffer_.clear();
  if (error) std::rethrow_exception(error);
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
    if (!parseReal(s, v)) fail(column, "expected a finite number within +-1e9, got '" + std::string(s) + "'");
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
    return !s.empty() && res.ec == std::errc() && res.ptr == s.data() + s.size() && std::abs(v) <= kMaxNumber;
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
      if (colon == std::string_view::npos || !parseReal(item.substr(0, colon), x) ||
          !parseReal(item.substr(colon + 1), y))
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
std::size_t splitCsvLine(const char* begin, const char* end, RowParser::Fields& fields) {
  std::size_t n = 0;
  const char* start = begin;
  while (true) {
    const auto* comma = static_cast<const char*>(std::memchr(start, ',', static_cast<std::size_t>(end - start)));
    const char* field_end = comma == nullptr ? end : comma;
    if (n < kColumns) fields[n] = std::string_view(start, static_cast<std::size_t>(field_end - start));
    ++n;
    if (comma == nullptr) return n;
    start = comma + 1;
  }
}

constexpr std::size_t kBlockSize = std::size_t{1} << 18;  // bytes read at a time
constexpr std::size_t kCopyFlush = std::size_t{1} << 17;  // bytes of copied rows written at a time

}  // namespace

StatesCsvReader::StatesCsvReader(const fs::path& file, SampleRate rate) : file_(file), rate_(rate) {
  // A folder opens too, and fails only when read ("read error").
  std::error_code ec;
  if (fs::exists(file, ec) && !fs::is_regular_file(file, ec))
    throw ConfigError(file.string(), 0, "", "not a regular file");
  fd_ = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw ConfigError(file.string(), 0, "", "cannot open the file");
  std::error_code size_error;
  file_size_ = fs::file_size(file, size_error);
  if (size_error) file_size_ = 0;
  block_.resize(kBlockSize);
  const char* begin = nullptr;
  const char* end = nullptr;
  if (!nextLine(begin, end)) throw ConfigError(file.string(), 1, "header", "the file is empty");
  if (std::string_view(begin, static_cast<std::size_t>(end - begin)) != kStatesCsvHeader)
    throw ConfigError(file.string(), 1, "header", "expected '" + std::string(kStatesCsvHeader) + "'");
}

void StatesCsvReader::copyKeptRowsTo(std::FILE* sink) {
  copy_ = sink;
  copy_buffer_.clear();
  if (copy_ == nullptr) return;
  copy_buffer_.append(kStatesCsvHeader);
  copy_buffer_.push_back('\n');
}

StatesCsvReader::~StatesCsvReader() {
  if (fd_ >= 0) ::close(fd_);
}

// The next line without its '\n' (and '\r'); false at the end of the file.
bool StatesCsvReader::nextLine(const char*& begin, const char*& end) {
  while (true) {
    const char* data = block_.data();
    const auto* newline = static_cast<const char*>(std::memchr(data + block_begin_, '\n', block_end_ - block_begin_));
    if (newline != nullptr || (eof_ && block_begin_ < block_end_)) {
      begin = data + block_begin_;
      end = newline != nullptr ? newline : data + block_end_;
      const std::size_t consumed = static_cast<std::size_t>(end - begin) + (newline != nullptr ? 1 : 0);
      block_begin_ += consumed;
      bytes_read_ += consumed;
      if (end > begin && end[-1] == '\r') --end;
      ++line_;
      return true;
    }
    if (eof_) return false;
    // Keep the partial line, grow the block when one line fills it, read more.
    const std::size_t partial = block_end_ - block_begin_;
    if (block_begin_ > 0) std::memmove(block_.data(), block_.data() + block_begin_, partial);
    block_begin_ = 0;
    block_end_ = partial;
    if (block_end_ == block_.size()) block_.resize(block_.size() * 2);
    const ssize_t n = ::read(fd_, block_.data() + block_end_, block_.size() - block_end_);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw ConfigError(file_.string(), line_, "", "read error");
    }
    if (n == 0) eof_ = true;
    block_end_ += static_cast<std::size_t>(n);
  }
}

void StatesCsvReader::copyText(const char* begin, std::size_t size) {
  copy_buffer_.append(begin, size);
  copy_buffer_.push_back('\n');
  if (copy_buffer_.size() >= kCopyFlush) flushCopy();
}

void StatesCsvReader::flushCopy() {
  if (copy_ == nullptr || copy_buffer_.empty()) return;
  if (std::fwrite(copy_buffer_.data(), 1, copy_buffer_.size(), copy_) != copy_buffer_.size())
    throw std::runtime_error(std::string("cannot copy the rows of ") + file_.string() + ": " + std::strerror(errno));
  copy_buffer_.clear();
}

void StatesCsvReader::commit(Recording& into) {
  if (have_sample_ && keep_sample_) {
    const std::uint32_t base = into.addObstacles(points_);
    robot_.obstacles_begin += base;
    for (auto& a : agents_) a.obstacles_begin += base;
    into.addSample(sample_t_, robot_, agents_);
  }
  have_sample_ = false;
  agents_.clear();
  points_.clear();
}

namespace {

// One row of states.csv, parsed.
struct ParsedRow {
  bool robot = false;
  double t = 0.0;
  std::string_view t_text;
  EntityState e;
};

// The checked parser: every field of the row in order, ConfigError (file:line: column: what) at the
// first problem. `points` receives the obstacle points.
void parseRowChecked(const fs::path& file, int line, const char* begin, const char* end, bool have_sample,
                     double sample_t, const std::string& sample_t_text, ParsedRow& out, std::vector<Vec2>& points) {
  RowParser::Fields fields;
  const std::size_t count = splitCsvLine(begin, end, fields);
  if (count != kColumns)
    throw ConfigError(file.string(), line, "row", fmt::format("expected {} fields, got {}", kColumns, count));
  const RowParser row(file, line, fields);

  const std::string_view kind = row.text(kKind);
  out.robot = kind == "robot";
  // An agent row repeats its tick's time: when the text is the robot row's, so is the value.
  const bool same_time_text = !out.robot && have_sample && row.text(kT) == sample_t_text;
  out.t = same_time_text ? sample_t : row.real(kT);
  out.t_text = row.text(kT);
  if (!out.robot && kind != "agent") row.fail(kKind, "expected robot or agent, got '" + std::string(kind) + "'");
  EntityState& e = out.e;
  e = EntityState();
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
  if (!kRadiusBound.contains(e.radius))
    row.fail(kRadius, "must be in " + boundText(kRadiusBound) + " m (the bound of the messages' checks), got '" +
                          std::string(row.text(kRadius)) + "'");
  e.behavior = row.integer<std::int8_t>(kBehavior);
  e.behavior_state = row.integer<std::int8_t>(kBehaviorState);
  e.group = row.integer<std::int32_t>(kGroup);
  const bool goal_empty = row.text(kGoalX).empty() && row.text(kGoalY).empty() && row.text(kGoalRadius).empty();
  if (!goal_empty) {
    e.has_goal = true;
    e.goal_x = row.real(kGoalX);
    e.goal_y = row.real(kGoalY);
    e.goal_radius = row.real(kGoalRadius);
  }
  row.obstacles(points);
  e.obstacles_count = static_cast<std::uint32_t>(points.size());
}

// The fast parser: a well-formed row read left to right in one pass (the numbers' ends are the
// separators). Returns false, with `out` unspecified, on anything unusual: the checked parser then
// reads the row again and names the problem.
class FastRow {
 public:
  FastRow(const char* begin, const char* end) : p_(begin), end_(end) {}

  bool parse(bool have_sample, double sample_t, const std::string& sample_t_text, ParsedRow& out,
             std::vector<Vec2>& points) {
    points.clear();
    const char* t_begin = p_;
    if (have_sample && static_cast<std::size_t>(end_ - p_) > sample_t_text.size() &&
        std::memcmp(p_, sample_t_text.data(), sample_t_text.size()) == 0 && p_[sample_t_text.size()] == ',') {
      out.t = sample_t;
      p_ += sample_t_text.size() + 1;
    } else if (!real(out.t, ',')) {
      return false;
    }
    out.t_text = std::string_view(t_begin, static_cast<std::size_t>(p_ - 1 - t_begin));
    if (literal("robot,")) {
      out.robot = true;
    } else if (literal("agent,")) {
      out.robot = false;
    } else {
      return false;
    }
    EntityState& e = out.e;
    e = EntityState();
    if (!integer(e.id, ',') || !real(e.x, ',') || !real(e.y, ',') || !real(e.yaw, ',') || !real(e.vx, ',') ||
        !real(e.vy, ',') || !real(e.vyaw, ',') || !real(e.linear_vel, ',') || !real(e.angular_vel, ',') ||
        !real(e.radius, ',') || !integer(e.behavior, ',') || !integer(e.behavior_state, ',') || !integer(e.group, ','))
      return false;
    if (!kRadiusBound.contains(e.radius)) return false;  // the checked parser names it
    if (literal(",,,")) {
      e.has_goal = false;
    } else if (real(e.goal_x, ',') && real(e.goal_y, ',') && real(e.goal_radius, ',')) {
      e.has_goal = true;
    } else {
      return false;
    }
    while (p_ < end_) {
      double x = 0.0;
      double y = 0.0;
      if (!real(x, ':') || !real(y, ';', true)) return false;
      points.emplace_back(x, y);
    }
    e.obstacles_count = static_cast<std::uint32_t>(points.size());
    return true;
  }

 private:
  bool literal(std::string_view text) {
    if (static_cast<std::size_t>(end_ - p_) < text.size() || std::memcmp(p_, text.data(), text.size()) != 0)
      return false;
    p_ += text.size();
    return true;
  }
  // The separator after the value: `sep`, or (last = true) the end of the line, where a
  // separator before the end must be followed by more.
  bool separator(const char* after, char sep, bool last) {
    if (after == end_) {
      p_ = after;
      return last;
    }
    if (*after != sep || (last && after + 1 == end_)) return false;
    p_ = after + 1;
    return true;
  }
  bool real(double& v, char sep, bool last = false) {
    const auto res = std::from_chars(p_, end_, v);
    if (res.ec != std::errc() || res.ptr == p_ || !(std::abs(v) <= kMaxNumber)) return false;
    return separator(res.ptr, sep, last);
  }
  template <class Int>
  bool integer(Int& v, char sep) {
    long long x = 0;
    const auto res = std::from_chars(p_, end_, x);
    if (res.ec != std::errc() || res.ptr == p_ || x < static_cast<long long>(std::numeric_limits<Int>::min()) ||
        x > static_cast<long long>(std::numeric_limits<Int>::max()))
      return false;
    v = static_cast<Int>(x);
    return separator(res.ptr, sep, false);
  }

  const char* p_;
  const char* end_;
};

}  // namespace

bool StatesCsvReader::read(Recording& into, std::size_t max_samples) {
  const std::size_t target = into.size() + max_samples;
  ParsedRow row;
  const char* begin = nullptr;
  const char* end = nullptr;
  while (into.size() < target) {
    if (!nextLine(begin, end)) {
      commit(into);
      flushCopy();
      return false;
    }
    if (begin == end) continue;
    if (!FastRow(begin, end).parse(have_sample_, sample_t_, sample_t_text_, row, row_points_))
      parseRowChecked(file_, line_, begin, end, have_sample_, sample_t_, sample_t_text_, row, row_points_);
    EntityState& e = row.e;

    if (row.robot) {
      commit(into);
      if (any_robot_row_ && !(row.t > previous_robot_t_))
        throw ConfigError(file_.string(), line_, kColumnNames[kT],
                          fmt::format("time {} s does not follow the previous tick's {} s", row.t, previous_robot_t_));
      any_robot_row_ = true;
      previous_robot_t_ = row.t;
      have_sample_ = true;
      keep_sample_ = rate_.keep(row.t);
      sample_t_ = row.t;
      sample_t_text_.assign(row.t_text);
      if (keep_sample_) {
        e.obstacles_begin = 0;
        points_.insert(points_.end(), row_points_.begin(), row_points_.end());
        robot_ = e;
      }
    } else {
      if (!have_sample_)
        throw ConfigError(file_.string(), line_, kColumnNames[kKind], "agent row before the first robot row");
      if (row.t != sample_t_)
        throw ConfigError(file_.string(), line_, kColumnNames[kT],
                          fmt::format("agent row at {} s inside the tick of {} s", row.t, sample_t_));
      if (keep_sample_) {
        e.obstacles_begin = static_cast<std::uint32_t>(points_.size());
        points_.insert(points_.end(), row_points_.begin(), row_points_.end());
        agents_.push_back(e);
      }
    }
    if (keep_sample_ && copy_ != nullptr) copyText(begin, static_cast<std::size_t>(end - begin));
  }
  return true;
}

Recording readStatesCsv(const fs::path& file) {
  StatesCsvReader reader(file);
  Recording rec;
  // After the first rows, reserve for the whole file from the bytes per sample seen so far (2 %
  // spare): growing vectors by doubling would hold two copies of a long recording at once.
  if (!reader.read(rec, 256)) return rec;
  if (reader.fileSize() > 0 && reader.bytesRead() > 0 && !rec.empty()) {
    const double scale = 1.02 * static_cast<double>(reader.fileSize()) / static_cast<double>(reader.bytesRead());
    rec.reserve(static_cast<std::size_t>(scale * static_cast<double>(rec.size() + 1)),
                static_cast<std::size_t>(scale * static_cast<double>(rec.agentRows() + 1)),
                static_cast<std::size_t>(scale * static_cast<double>(rec.obstaclePoints() + 1)));
  }
  while (reader.read(rec, std::numeric_limits<std::size_t>::max() / 2)) {
  }
  return rec;
}

}  // namespace hunav::results
