#include "hunav/scenario.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <system_error>
#include <utility>

#include "hunav/agents_file.hpp"
#include "hunav/episode_status.hpp"
#include "hunav/map_server_map.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav {

namespace {

// ---------------------------------------------------------------------------------------------------
// ROS map_server maps
// ---------------------------------------------------------------------------------------------------

struct Image {
  int width = 0;
  int height = 0;
  int maxval = 0;
  std::vector<int> pixels;  // row-major, row 0 = the top line of the picture
};

// A netpbm grey map, binary (P5, 8 or 16 bit) or plain (P2). Errors are reported at the map yaml's
// `image:` line (a PGM has no keys).
Image readPgm(const std::string& path, const std::string& yaml_path, int yaml_line) {
  auto fail = [&](const std::string& what) -> Image {
    throw ConfigError(yaml_path, yaml_line, "image", path + ": " + what);
  };
  // A folder opens as a stream on Linux and fails only when read (basic_filebuf::underflow).
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    return fail("not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail("cannot open the image");
  std::string data;
  try {
    data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::ios_base::failure& e) {  // a read error throws from the stream
    return fail(std::string("cannot read the image: ") + e.what());
  }
  std::size_t pos = 0;
  auto skipSpaceAndComments = [&] {
    while (pos < data.size()) {
      if (std::isspace(static_cast<unsigned char>(data[pos]))) {
        ++pos;
      } else if (data[pos] == '#') {
        while (pos < data.size() && data[pos] != '\n') ++pos;
      } else {
        break;
      }
    }
  };
  // A decimal header or plain-raster number, at most `max`.
  auto number = [&](const char* what, long max) -> long {
    skipSpaceAndComments();
    if (pos >= data.size() || !std::isdigit(static_cast<unsigned char>(data[pos])))
      fail(std::string("expected ") + what + (pos >= data.size() ? " (the file ends early)" : ""));
    long v = 0;
    while (pos < data.size() && std::isdigit(static_cast<unsigned char>(data[pos]))) {
      v = v * 10 + (data[pos++] - '0');
      if (v > max) fail(std::string(what) + " is larger than " + std::to_string(max));
    }
    return v;
  };
  if (data.size() < 2 || data[0] != 'P' || (data[1] != '5' && data[1] != '2'))
    return fail(
        "not a PGM image (expected the magic number P5 or P2; convert PNG maps with e.g. `convert map.png map.pgm`)");
  const bool binary = data[1] == '5';
  pos = 2;
  constexpr long kMaxSide = 20000;  // cells; 1 km at 5 cm
  Image img;
  img.width = static_cast<int>(number("the width", kMaxSide));
  img.height = static_cast<int>(number("the height", kMaxSide));
  img.maxval = static_cast<int>(number("the maximum grey value", 65535));
  if (img.width < 1 || img.height < 1) fail("the width and height must be >= 1");
  if (img.maxval < 1) fail("the maximum grey value must be >= 1");
  const std::size_t count = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  // The file must be large enough for the raster before anything is allocated for it.
  if (binary) {
    // Exactly one whitespace character separates the header from the raster.
    if (pos >= data.size() || !std::isspace(static_cast<unsigned char>(data[pos])))
      fail("expected one whitespace character after the header");
    ++pos;
    const std::size_t bytes_per_pixel = img.maxval > 255 ? 2 : 1;
    if (data.size() - pos < count * bytes_per_pixel)
      fail("the raster is truncated: " + std::to_string((data.size() - pos) / bytes_per_pixel) + " of " +
           std::to_string(count) + " pixels");
    img.pixels.resize(count);
    const auto* raster = reinterpret_cast<const unsigned char*>(data.data() + pos);
    for (std::size_t i = 0; i < count; ++i) {
      const int v = bytes_per_pixel == 2 ? (raster[2 * i] << 8) | raster[2 * i + 1] : raster[i];
      if (v > img.maxval) fail("pixel " + std::to_string(i) + " exceeds the maximum grey value");
      img.pixels[i] = v;
    }
  } else {
    if (data.size() - pos < 2 * count - 1)  // a digit and a separator per pixel at least
      fail("the raster is truncated: too short for " + std::to_string(count) + " pixels");
    img.pixels.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
      const long v = number("a pixel value", 65535);
      if (v > img.maxval) fail("pixel " + std::to_string(i) + " exceeds the maximum grey value");
      img.pixels[i] = static_cast<int>(v);
    }
  }
  return img;
}

// map_server's `negate`: 0/1 or true/false.
bool readNegate(const YamlReader& yr, const YAML::Node& root) {
  const YAML::Node n = root["negate"];
  if (!n) return false;
  if (n.IsScalar()) {
    const std::string v = n.Scalar();
    if (v == "0" || v == "false") return false;
    if (v == "1" || v == "true") return true;
  }
  yr.fail(n, "negate", "expected 0 or 1");
}

// Greedy merge of occupied cells into rectangles: from the lowest row up and left to right, an unused
// occupied cell starts a rectangle that grows right as far as the row allows, then up while every cell
// of its span is occupied and unused. `occupied` is row-major with row 0 at the bottom (+y up).
struct CellRect {
  int col0, row0, col1, row1;  // inclusive
};
std::vector<CellRect> mergeCells(const std::vector<char>& occupied, int width, int height) {
  std::vector<char> used(occupied.size(), 0);
  auto free_to_take = [&](int c, int r) {
    const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(width) + static_cast<std::size_t>(c);
    return occupied[i] && !used[i];
  };
  std::vector<CellRect> rects;
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      if (!free_to_take(c, r)) continue;
      int c1 = c;
      while (c1 + 1 < width && free_to_take(c1 + 1, r)) ++c1;
      int r1 = r;
      for (bool grow = true; grow && r1 + 1 < height;) {
        for (int x = c; x <= c1 && grow; ++x) grow = free_to_take(x, r1 + 1);
        if (grow) ++r1;
      }
      for (int y = r; y <= r1; ++y)
        for (int x = c; x <= c1; ++x)
          used[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] = 1;
      rects.push_back(CellRect{c, r, c1, r1});
    }
  }
  return rects;
}

std::filesystem::path relativeTo(const std::string& file, const std::string& name) {
  std::filesystem::path p = name;
  if (p.is_relative()) p = std::filesystem::path(file).parent_path() / p;
  return p;
}

void checkCoordinates(const YamlReader& yr, const YAML::Node& at, const std::string& key, const Vec2& p) {
  if (std::abs(p.x()) > kMaxCoordinate || std::abs(p.y()) > kMaxCoordinate)
    yr.fail(at, key, "coordinates must be within +-1e5 m");
}

Vec2 readXY(const YamlReader& yr, const YAML::Node& n, const std::string& key) {
  Vec2 p;
  if (n.IsSequence()) {
    if (n.size() != 2) yr.fail(n, key, "expected [x, y]");
    p = Vec2(yr.convert<double>(n[0], key), yr.convert<double>(n[1], key));
  } else if (n.IsMap()) {
    p = Vec2(yr.get<double>(n, "x", key), yr.get<double>(n, "y", key));
  } else {
    yr.fail(n, key, "expected [x, y] or {x, y}");
  }
  checkCoordinates(yr, n, key, p);
  return p;
}

// A yaw (rad) within +-kMaxAngle: Box2D keeps angles in float.
double readYaw(const YamlReader& yr, const YAML::Node& map, const std::string& key, const std::string& where) {
  const double yaw = yr.get<double>(map, key, where, 0.0);
  if (std::abs(yaw) > kMaxAngle) yr.fail(map[key], YamlReader::join(where, key), "must be within +-1e3 rad");
  return yaw;
}

// A size (m) in [kMinBodySize, max].
void checkSize(const YamlReader& yr, const YAML::Node& at, const std::string& key, double v, double max,
               const char* max_text) {
  if (v <= 0.0) yr.fail(at, key, "must be > 0");
  if (!(v >= kMinBodySize && v <= max)) yr.fail(at, key, std::string("must be in [1e-3, ") + max_text + "] m");
}

// Every point of a static shape within +-kMaxCoordinate.
void checkShapeExtent(const YamlReader& yr, const YAML::Node& at, const std::string& key, const Shape& sh) {
  Vec2 lo, hi;
  sh.bounds(lo, hi);
  if (lo.cwiseAbs().maxCoeff() > kMaxCoordinate || hi.cwiseAbs().maxCoeff() > kMaxCoordinate)
    yr.fail(at, key, "the shape reaches beyond +-1e5 m");
}

std::vector<Vec2> readPoints(const YamlReader& yr, const YAML::Node& n, const std::string& key, std::size_t min) {
  if (!n.IsSequence()) yr.fail(n, key, "expected a list of points");
  std::vector<Vec2> pts;
  for (const YAML::Node& p : n) pts.push_back(readXY(yr, p, key));
  if (pts.size() < min) yr.fail(n, key, "needs at least " + std::to_string(min) + " points");
  return pts;
}

void readMap(const YamlReader& yr, const YAML::Node& map, Scenario& s) {
  if (const YAML::Node ms = yr.child(map, "map_server", "map", false)) {
    // One map file, or a list of them; relative to the scenario file.
    std::vector<YAML::Node> files;
    if (ms.IsSequence()) {
      for (const YAML::Node& f : ms) files.push_back(f);
    } else {
      files.push_back(ms);
    }
    for (const YAML::Node& f : files) {
      const std::string name = yr.convert<std::string>(f, "map.map_server");
      const std::filesystem::path p = relativeTo(yr.path(), name);
      std::error_code ec;  // a symlink loop is an error code here, not a filesystem_error (exit 1)
      if (!std::filesystem::is_regular_file(p, ec))
        yr.fail(f, "map.map_server", "cannot read the map file '" + p.string() + "'" + (ec ? ": " + ec.message() : ""));
      OccupancyMapFrame frame;
      for (Shape& sh : loadOccupancyMap(p.string(), &frame)) {
        checkShapeExtent(yr, f, "map.map_server", sh);
        s.shapes.push_back(std::move(sh));
      }
      // The first map's cells are the published grid's (a turned map's cells cannot be).
      if (&f == &files.front()) {
        s.map_grid.resolution = frame.resolution;
        s.map_grid.anchor = frame.yaw == 0.0 ? frame.origin : Vec2::Zero();
      }
    }
  }
  auto list = [&](const char* key) -> YAML::Node {
    const YAML::Node n = yr.child(map, key, "map", false);
    if (n && !n.IsSequence()) yr.fail(n, std::string("map.") + key, "expected a list");
    return n;
  };
  for (const YAML::Node& w : list("walls")) {
    Shape sh;
    sh.kind = Shape::Kind::Polyline;
    sh.points = readPoints(yr, w, "map.walls", 2);
    s.shapes.push_back(sh);
  }
  for (const YAML::Node& p : list("polygons")) {
    Shape sh;
    sh.kind = Shape::Kind::Polygon;
    sh.points = readPoints(yr, p, "map.polygons", 3);
    s.shapes.push_back(sh);
  }
  for (const YAML::Node& b : list("boxes")) {
    const Vec2 c = readXY(yr, b, "map.boxes");
    const double w = yr.get<double>(b, "width", "map.boxes");
    const double h = yr.get<double>(b, "height", "map.boxes");
    const double yaw = readYaw(yr, b, "yaw", "map.boxes");
    checkSize(yr, b["width"], "map.boxes.width", w, 2.0 * kMaxCoordinate, "2e5");
    checkSize(yr, b["height"], "map.boxes.height", h, 2.0 * kMaxCoordinate, "2e5");
    Shape sh;
    sh.kind = Shape::Kind::Polygon;
    const double cs = std::cos(yaw), sn = std::sin(yaw);
    for (const Vec2& corner : {Vec2(-w / 2, -h / 2), Vec2(w / 2, -h / 2), Vec2(w / 2, h / 2), Vec2(-w / 2, h / 2)})
      sh.points.push_back(c + Vec2(cs * corner.x() - sn * corner.y(), sn * corner.x() + cs * corner.y()));
    checkShapeExtent(yr, b, "map.boxes", sh);
    s.shapes.push_back(sh);
  }
  for (const YAML::Node& c : list("circles")) {
    Shape sh;
    sh.kind = Shape::Kind::Circle;
    sh.center = readXY(yr, c, "map.circles");
    sh.radius = yr.get<double>(c, "radius", "map.circles");
    checkSize(yr, c["radius"], "map.circles.radius", sh.radius, kMaxCoordinate, "1e5");
    checkShapeExtent(yr, c, "map.circles", sh);
    s.shapes.push_back(sh);
  }
}

// `shape`: a circle of `radius`, or a box of `length` x `width`.
void readRobotShape(const YamlReader& yr, const YAML::Node& r, RobotConfig& robot) {
  const std::string shape = yr.get<std::string>(r, "shape", "robot", "circle");
  if (shape == "circle") {
    robot.shape = RobotShape::Circle;
    robot.radius = yr.get<double>(r, "radius", "robot", robot.radius);
    checkSize(yr, r["radius"], "robot.radius", robot.radius, kMaxBodySize, "100");
    for (const char* key : {"length", "width"})
      if (r[key]) yr.fail(r[key], std::string("robot.") + key, "only for shape: box");
  } else if (shape == "box") {
    robot.shape = RobotShape::Box;
    robot.length = yr.get<double>(r, "length", "robot");
    robot.width = yr.get<double>(r, "width", "robot");
    checkSize(yr, r["length"], "robot.length", robot.length, kMaxBodySize, "100");
    checkSize(yr, r["width"], "robot.width", robot.width, kMaxBodySize, "100");
    if (r["radius"])
      yr.fail(r["radius"], "robot.radius", "a box robot's radius is its half diagonal: leave radius out");
    robot.radius = 0.5 * std::hypot(robot.length, robot.width);
  } else {
    yr.fail(r["shape"], "robot.shape", "expected circle or box, got '" + shape + "'");
  }
}

void readRobotDrive(const YamlReader& yr, const YAML::Node& r, RobotConfig& robot) {
  const std::string drive = yr.get<std::string>(r, "drive", "robot", "differential");
  if (drive == "differential")
    robot.drive = RobotDrive::Differential;
  else if (drive == "holonomic")
    robot.drive = RobotDrive::Holonomic;
  else
    yr.fail(r["drive"], "robot.drive", "expected differential or holonomic, got '" + drive + "'");
}

// `start` (required) and `goal` (optional), each a pose; the goal with its radius.
void readRobotStartAndGoal(const YamlReader& yr, const YAML::Node& r, RobotConfig& robot) {
  const YAML::Node start = yr.child(r, "start", "robot", true);
  robot.start = readXY(yr, start, "robot.start");
  robot.start_yaw = readYaw(yr, start, "yaw", "robot.start");
  if (const YAML::Node goal = yr.child(r, "goal", "robot", false)) {
    robot.has_goal = true;
    robot.goal = readXY(yr, goal, "robot.goal");
    robot.goal_yaw = readYaw(yr, goal, "yaw", "robot.goal");
    robot.goal_radius = yr.get<double>(goal, "radius", "robot.goal", robot.goal_radius);
    if (robot.goal_radius <= 0.0) yr.fail(goal["radius"], "robot.goal.radius", "must be > 0");
    if (robot.goal_radius > kMaxCoordinate) yr.fail(goal["radius"], "robot.goal.radius", "must be <= 1e5 m");
  }
}

// `limits`: speeds and accelerations (the lateral ones of a holonomic base only).
void readRobotLimits(const YamlReader& yr, const YAML::Node& r, RobotConfig& robot) {
  if (const YAML::Node l = yr.child(r, "limits", "robot", false)) {
    RobotLimits& lim = robot.limits;
    lim.max_v = yr.get<double>(l, "max_v", "robot.limits", lim.max_v);
    lim.min_v = yr.get<double>(l, "min_v", "robot.limits", lim.min_v);
    lim.max_w = yr.get<double>(l, "max_w", "robot.limits", lim.max_w);
    lim.max_acc_v = yr.get<double>(l, "max_acc_v", "robot.limits", lim.max_acc_v);
    lim.max_acc_w = yr.get<double>(l, "max_acc_w", "robot.limits", lim.max_acc_w);
    // Lateral limits of a holonomic base: by default those of the forward axis.
    lim.max_vy = yr.get<double>(l, "max_vy", "robot.limits", lim.max_v);
    lim.max_acc_vy = yr.get<double>(l, "max_acc_vy", "robot.limits", lim.max_acc_v);
    if (robot.drive != RobotDrive::Holonomic)
      for (const char* key : {"max_vy", "max_acc_vy"})
        if (l[key]) yr.fail(l[key], std::string("robot.limits.") + key, "only for drive: holonomic");
    // The forward limits first: max_vy and max_acc_vy default to them, and a bad max_v must be named
    // as max_v, not as the max_vy it was copied into.
    if (lim.max_v <= 0.0) yr.fail(l["max_v"], "robot.limits.max_v", "must be > 0");
    if (lim.max_acc_v <= 0.0) yr.fail(l["max_acc_v"], "robot.limits.max_acc_v", "must be > 0");
    if (lim.max_vy < 0.0) yr.fail(l["max_vy"], "robot.limits.max_vy", "must be >= 0");
    if (lim.max_acc_vy <= 0.0) yr.fail(l["max_acc_vy"], "robot.limits.max_acc_vy", "must be > 0");
    if (lim.min_v > lim.max_v) yr.fail(l["min_v"], "robot.limits.min_v", "must be <= max_v");
    if (lim.max_w <= 0.0) yr.fail(l["max_w"], "robot.limits.max_w", "must be > 0");
    if (lim.max_acc_w <= 0.0) yr.fail(l["max_acc_w"], "robot.limits.max_acc_w", "must be > 0");
    if (lim.max_v > kMaxSpeed) yr.fail(l["max_v"], "robot.limits.max_v", "must be <= 10 m/s");
    if (lim.min_v < -kMaxSpeed) yr.fail(l["min_v"], "robot.limits.min_v", "must be >= -10 m/s");
    if (lim.max_vy > kMaxSpeed) yr.fail(l["max_vy"], "robot.limits.max_vy", "must be <= 10 m/s");
    if (lim.max_w > kMaxYawRate) yr.fail(l["max_w"], "robot.limits.max_w", "must be <= 100 rad/s");
    for (const auto& [key, value] : {std::pair<const char*, double>{"max_acc_v", lim.max_acc_v},
                                     {"max_acc_w", lim.max_acc_w},
                                     {"max_acc_vy", lim.max_acc_vy}})
      if (value > kMaxAcceleration) yr.fail(l[key], std::string("robot.limits.") + key, "must be <= 1e3");
  }
}

void readRobotLaser(const YamlReader& yr, const YAML::Node& r, RobotConfig& robot) {
  if (const YAML::Node l = yr.child(r, "laser", "robot", false)) {
    LaserConfig& las = robot.laser;
    las.beams = yr.get<int>(l, "beams", "robot.laser", las.beams);
    las.fov = yr.get<double>(l, "fov", "robot.laser", las.fov);
    las.range_min = yr.get<double>(l, "range_min", "robot.laser", las.range_min);
    las.range_max = yr.get<double>(l, "range_max", "robot.laser", las.range_max);
    las.noise_std = yr.get<double>(l, "noise_std", "robot.laser", las.noise_std);
    if (las.beams < 1 || las.beams > 100000) yr.fail(l["beams"], "robot.laser.beams", "must be 1..100000");
    if (las.fov <= 0.0 || las.fov > 2.0 * kPi) yr.fail(l["fov"], "robot.laser.fov", "must be in (0, 2*pi]");
    if (las.range_max <= las.range_min || las.range_min < 0.0)
      yr.fail(l, "robot.laser", "needs 0 <= range_min < range_max");
    if (las.range_max > kMaxSensorRange) yr.fail(l["range_max"], "robot.laser.range_max", "must be <= 1e3 m");
    // Noise beyond the sensor's own reach is no measurement at all.
    if (las.noise_std < 0.0 || las.noise_std > kMaxSensorRange)
      yr.fail(l["noise_std"], "robot.laser.noise_std", "must be in [0, 1e3] m");
  }
}

// What the robot perceives of the people, and how often its planner runs.
void readRobotPerceptionAndRate(const YamlReader& yr, const YAML::Node& r, RobotConfig& robot) {
  robot.perception_range = yr.get<double>(r, "perception_range", "robot", robot.perception_range);
  if (robot.perception_range < 0.0 || robot.perception_range > kMaxSensorRange)
    yr.fail(r["perception_range"], "robot.perception_range", "must be in [0, 1e3] m");
  robot.perception_fov = yr.get<double>(r, "perception_fov", "robot", robot.perception_fov);
  if (robot.perception_fov <= 0.0 || robot.perception_fov > 2.0 * kPi)
    yr.fail(r["perception_fov"], "robot.perception_fov", "must be in (0, 2*pi]");
  robot.perception_noise_std = yr.get<double>(r, "perception_noise_std", "robot", robot.perception_noise_std);
  if (robot.perception_noise_std < 0.0 || robot.perception_noise_std > kMaxSensorRange)
    yr.fail(r["perception_noise_std"], "robot.perception_noise_std", "must be in [0, 1e3] m");
  robot.control_rate = yr.get<double>(r, "control_rate", "robot", robot.control_rate);
  // 1 / (control_rate * dt) ticks must be a number the clock can count.
  if (!(robot.control_rate >= 1e-3)) yr.fail(r["control_rate"], "robot.control_rate", "must be >= 1e-3 Hz");
}

void readRobot(const YamlReader& yr, const YAML::Node& r, RobotConfig& robot) {
  robot.id = yr.get<int>(r, "id", "robot", robot.id);
  readRobotShape(yr, r, robot);
  readRobotDrive(yr, r, robot);
  readRobotStartAndGoal(yr, r, robot);
  readRobotLimits(yr, r, robot);
  readRobotLaser(yr, r, robot);
  readRobotPerceptionAndRate(yr, r, robot);
}

// A point must keep `clearance` from every static shape.
void checkClear(const YamlReader& yr, const Scenario& s, const YAML::Node& at, const std::string& key, const Vec2& p,
                double clearance, const char* what) {
  for (const Shape& sh : s.shapes)
    if (sh.distance(p) < clearance)
      yr.fail(at, key, std::string(what) + " is inside a wall or closer to one than the robot radius");
}

}  // namespace

double defaultStuckTimeout(const RobotConfig& robot) {
  if (!robot.has_goal) return 0.0;
  const double straight = (robot.goal - robot.start).norm() / robot.limits.max_v;
  return std::min(kMaxTimeLimit, std::max(kMinDefaultStuckTimeout, kDefaultStuckFactor * straight));
}

void checkDurationOverride(double duration) {
  if (!(duration > 0.0 && duration <= kMaxTimeLimit))
    throw ConfigError("--duration", 0, "", "must be a number of seconds in (0, 1e7]");
}

MapServerMap loadMapServerMap(const std::string& yaml_path) {
  YamlReader yr(yaml_path);
  const YAML::Node& root = yr.root();
  const YAML::Node image_node = yr.child(root, "image", "", true);
  const std::string image = yr.convert<std::string>(image_node, "image");
  MapServerMap grid;
  grid.resolution = yr.get<double>(root, "resolution", "");
  if (grid.resolution <= 0.0) yr.fail(root["resolution"], "resolution", "must be > 0 (m per cell)");
  const YAML::Node origin_node = yr.child(root, "origin", "", true);
  if (!origin_node.IsSequence() || (origin_node.size() != 3 && origin_node.size() != 2))
    yr.fail(origin_node, "origin", "expected [x, y, yaw]");
  grid.origin = Vec2(yr.convert<double>(origin_node[0], "origin"), yr.convert<double>(origin_node[1], "origin"));
  checkCoordinates(yr, origin_node, "origin", grid.origin);
  grid.yaw = origin_node.size() == 3 ? yr.convert<double>(origin_node[2], "origin") : 0.0;
  if (std::abs(grid.yaw) > kMaxAngle) yr.fail(origin_node, "origin", "the yaw must be within +-1e3 rad");
  const bool negate = readNegate(yr, root);
  const double occupied_thresh = yr.get<double>(root, "occupied_thresh", "", 0.65);
  const double free_thresh = yr.get<double>(root, "free_thresh", "", 0.196);
  if (occupied_thresh < 0.0 || occupied_thresh > 1.0)
    yr.fail(root["occupied_thresh"], "occupied_thresh", "must be in [0, 1]");
  if (free_thresh < 0.0 || free_thresh > occupied_thresh)
    yr.fail(root["free_thresh"], "free_thresh", "must be in [0, occupied_thresh]");
  const std::string mode = yr.get<std::string>(root, "mode", "", "trinary");
  if (mode != "trinary" && mode != "scale" && mode != "raw")
    yr.fail(root["mode"], "mode", "expected trinary, scale or raw, got '" + mode + "'");

  const Image img = readPgm(relativeTo(yaml_path, image).string(), yaml_path, YamlReader::lineOf(image_node));
  // map_server's rule: occupancy p = (maxval - value) / maxval (value / maxval with negate), occupied when
  // p > occupied_thresh, free when p < free_thresh, unknown in between. In raw mode the value is the
  // occupancy in percent (above 100: unknown).
  grid.width = img.width;
  grid.height = img.height;
  grid.cells.assign(img.pixels.size(), MapServerMap::kUnknown);
  grid.occupancy.assign(img.pixels.size(), -1.0f);
  for (int row = 0; row < img.height; ++row) {
    const int map_row = img.height - 1 - row;  // the picture's top line is the map's highest y
    for (int col = 0; col < img.width; ++col) {
      const int v = img.pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(img.width) +
                               static_cast<std::size_t>(col)];
      const std::size_t cell =
          static_cast<std::size_t>(map_row) * static_cast<std::size_t>(img.width) + static_cast<std::size_t>(col);
      bool occ, free;
      if (mode == "raw") {
        occ = v <= 100 && v > occupied_thresh * 100.0;
        free = v < free_thresh * 100.0;
        if (v <= 100) grid.occupancy[cell] = static_cast<float>(v / 100.0);
      } else {
        const double p =
            negate ? static_cast<double>(v) / img.maxval : static_cast<double>(img.maxval - v) / img.maxval;
        occ = p > occupied_thresh;
        free = p < free_thresh;
        grid.occupancy[cell] = static_cast<float>(p);
      }
      grid.cells[cell] = occ ? MapServerMap::kOccupied : free ? MapServerMap::kFree : MapServerMap::kUnknown;
    }
  }
  return grid;
}

std::vector<Shape> loadOccupancyMap(const std::string& yaml_path, OccupancyMapFrame* frame) {
  const MapServerMap grid = loadMapServerMap(yaml_path);
  if (frame != nullptr) *frame = OccupancyMapFrame{grid.resolution, grid.origin, grid.yaw};
  // Free and unknown cells are both free space for the world.
  std::vector<char> occupied(grid.cells.size(), 0);
  for (std::size_t i = 0; i < grid.cells.size(); ++i) occupied[i] = grid.cells[i] == MapServerMap::kOccupied;
  const double cs = std::cos(grid.yaw), sn = std::sin(grid.yaw);
  auto corner = [&](int col, int row) {  // lower left corner of cell (col, row); the map turns by yaw about origin
    const double x = col * grid.resolution, y = row * grid.resolution;
    return Vec2(grid.origin.x() + cs * x - sn * y, grid.origin.y() + sn * x + cs * y);
  };
  std::vector<Shape> shapes;
  for (const CellRect& r : mergeCells(occupied, grid.width, grid.height)) {
    Shape sh;
    sh.kind = Shape::Kind::Polygon;
    sh.points = {corner(r.col0, r.row0), corner(r.col1 + 1, r.row0), corner(r.col1 + 1, r.row1 + 1),
                 corner(r.col0, r.row1 + 1)};
    shapes.push_back(std::move(sh));
  }
  return shapes;
}

void Scenario::bounds(Vec2& lo, Vec2& hi, double margin) const {
  lo = hi = robot.start;
  auto grow = [&](const Vec2& a, const Vec2& b) {
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(b);
  };
  for (const Shape& sh : shapes) {
    Vec2 a, b;
    sh.bounds(a, b);
    grow(a, b);
  }
  if (robot.has_goal) grow(robot.goal, robot.goal);
  for (const AgentConfig& a : agents) {
    grow(a.position, a.position);
    for (const Vec2& g : a.goals) grow(g, g);
  }
  lo -= Vec2(margin, margin);
  hi += Vec2(margin, margin);
}

const char* obstaclePointsName(ObstaclePoints p) {
  switch (p) {
    case ObstaclePoints::Closest:
      return "closest";
    case ObstaclePoints::Each:
      return "each";
    case ObstaclePoints::Mean:
      return "mean";
  }
  return "?";
}

const char* peopleNavigationName(PeopleNavigation n) { return n == PeopleNavigation::Path ? "path" : "direct"; }

namespace {

// evaluation.metrics: a file relative to the scenario's folder, which must exist (its contents are
// the evaluator's to check, with its own file:line: key errors, before the run starts).
std::string readMetricsPath(const YamlReader& yr, const YAML::Node& evaluation, const std::string& scenario_file) {
  const YAML::Node node = yr.child(evaluation, "metrics", "evaluation", false);
  if (!node) return "";
  const std::string written = yr.convert<std::string>(node, "evaluation.metrics");
  if (written.empty()) yr.fail(node, "evaluation.metrics", "must name a metrics file");
  std::filesystem::path p = written;
  if (p.is_relative()) p = std::filesystem::path(scenario_file).parent_path() / p;
  std::error_code ec;
  if (!std::filesystem::exists(p, ec)) yr.fail(node, "evaluation.metrics", "cannot open the file '" + p.string() + "'");
  if (!std::filesystem::is_regular_file(p, ec))
    yr.fail(node, "evaluation.metrics", "'" + p.string() + "' is not a regular file");
  return p.lexically_normal().string();
}

// The `people:` keys of the human model (besides hunav_loader and generate).
void readPeopleModel(const YamlReader& yr, const YAML::Node& people, PeopleModel& m) {
  const std::string points =
      yr.get<std::string>(people, "obstacle_points", "people", obstaclePointsName(m.obstacle_points));
  if (points == "closest")
    m.obstacle_points = ObstaclePoints::Closest;
  else if (points == "each")
    m.obstacle_points = ObstaclePoints::Each;
  else if (points == "mean")
    m.obstacle_points = ObstaclePoints::Mean;
  else
    yr.fail(people["obstacle_points"], "people.obstacle_points", "must be closest, each or mean, got '" + points + "'");
  const std::string nav = yr.get<std::string>(people, "navigation", "people", peopleNavigationName(m.navigation));
  if (nav == "path")
    m.navigation = PeopleNavigation::Path;
  else if (nav == "direct")
    m.navigation = PeopleNavigation::Direct;
  else
    yr.fail(people["navigation"], "people.navigation", "must be path or direct, got '" + nav + "'");
  m.route_resolution = yr.get<double>(people, "route_resolution", "people", m.route_resolution);
  if (!(m.route_resolution >= 0.02 && m.route_resolution <= 1.0))
    yr.fail(people["route_resolution"], "people.route_resolution", "must be in [0.02, 1] m");
  m.give_way = yr.get<bool>(people, "give_way", "people", m.give_way);
  m.force_tolerance = yr.get<double>(people, "force_tolerance", "people", m.force_tolerance);
  if (!(m.force_tolerance >= 0.0 && m.force_tolerance <= 0.01))
    yr.fail(people["force_tolerance"], "people.force_tolerance", "must be in [0, 0.01]");
  if (const YAML::Node model = yr.child(people, "model", "people", false))
    m.model = resolveMotionModel(yr.convert<std::string>(model, "people.model"),
                                 std::filesystem::path(yr.path()).parent_path().string(), yr.path(),
                                 YamlReader::lineOf(model), "people.model");
}

// `expect:` (scenarios/README.md): metric name -> a number or true/false (equality) or {min, max}, and
// `status:` -> an end status. Metric names are the evaluator's, checked where the run is set up
// (runner::checkExpectations), since common does not know the evaluator's registry.
std::vector<Expectation> readExpectations(const YamlReader& yr, const YAML::Node& expect) {
  if (!expect.IsMap()) yr.fail(expect, "expect", "expected a mapping metric name -> condition");
  std::vector<Expectation> out;
  for (const auto& item : expect) {
    const std::string name = yr.convert<std::string>(item.first, "expect");
    const std::string key = "expect." + name;
    const YAML::Node& cond = item.second;
    Expectation e;
    e.metric = name;
    e.file = yr.path();
    e.line = YamlReader::lineOf(cond);
    for (const Expectation& earlier : out)
      if (earlier.metric == name) yr.fail(item.first, key, "given twice");
    if (name == "status") {
      e.kind = Expectation::Kind::Status;
      e.status = yr.convert<std::string>(cond, key);
      if (e.status != episode_status::kGoalReached && e.status != episode_status::kTimeLimit &&
          e.status != episode_status::kStuck)
        yr.fail(cond, key, "must be goal_reached, time_limit or stuck, got '" + e.status + "'");
    } else if (cond.IsScalar()) {
      e.kind = Expectation::Kind::Equal;
      const std::string text = cond.Scalar();
      if (text == "true" || text == "false") {
        e.is_bool = true;
        e.value = text == "true" ? 1.0 : 0.0;
      } else {
        const YAML::Node copy = cond;
        if (!YAML::convert<double>::decode(copy, e.value) || !std::isfinite(e.value))
          yr.fail(cond, key, "expected a number, true/false or {min: X, max: Y}, got '" + text + "'");
      }
    } else if (cond.IsMap()) {
      e.kind = Expectation::Kind::Range;
      for (const auto& bound : cond) {
        const std::string b = yr.convert<std::string>(bound.first, key);
        if (b == "min")
          e.min = yr.convert<double>(bound.second, key + ".min");
        else if (b == "max")
          e.max = yr.convert<double>(bound.second, key + ".max");
        else
          yr.fail(bound.first, key, "unknown key '" + b + "' (expected min and/or max)");
      }
      if (!e.min && !e.max) yr.fail(cond, key, "needs min, max or both");
      if (e.min && e.max && *e.min > *e.max) yr.fail(cond, key, "min is larger than max");
    } else {
      yr.fail(cond, key, "expected a number, true/false or {min: X, max: Y}");
    }
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace

std::string behaviorTreeReference(const std::string& scenario_file, const std::string& tree_path) {
  if (scenario_file.empty() || tree_path.empty()) return tree_path;
  // Both made absolute from the same working directory, so the relative path between them is the
  // same from wherever the run was started.
  std::error_code ec;
  const std::filesystem::path tree = std::filesystem::absolute(tree_path, ec).lexically_normal();
  const std::filesystem::path dir =
      std::filesystem::absolute(std::filesystem::path(scenario_file).parent_path(), ec).lexically_normal();
  if (ec) return tree_path;
  const std::filesystem::path rel = tree.lexically_relative(dir);
  return rel.empty() ? tree.string() : rel.string();
}

std::string resolveBehaviorTree(const std::string& scenario_file, const std::string& reference) {
  const std::filesystem::path ref = reference;
  if (scenario_file.empty() || reference.empty() || ref.is_absolute()) return reference;
  return (std::filesystem::path(scenario_file).parent_path() / ref).lexically_normal().string();
}

namespace {

void readScenarioName(const YamlReader& yr, const YAML::Node& root, const std::string& path, Scenario& s) {
  // The name becomes part of folder names (results/<name>_..., a batch's runs/<name>__...): a given
  // one may not climb out of them or hide; the default, the file's stem, is made safe.
  const auto safeChar = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  };
  if (root["name"]) {
    s.name = yr.get<std::string>(root, "name", "", "");
    if (s.name.empty() || s.name.size() > 100 || s.name.front() == '.' ||
        !std::all_of(s.name.begin(), s.name.end(), safeChar))
      yr.fail(root["name"], "name",
              "'" + s.name +
                  "' is not a safe folder name: use 1-100 letters, digits, '_', '-' or '.', not starting with '.'");
  } else {
    s.name = std::filesystem::path(path).stem().string();
    std::replace_if(
        s.name.begin(), s.name.end(), [&](char c) { return !safeChar(c); }, '_');
    s.name.erase(0, s.name.find_first_not_of('.'));
    if (s.name.empty()) s.name = "scenario";
  }
}

// The clock, the seed (unless overridden: seed_override >= 0), and the world's and stuck detector's settings.
void readSimulationSettings(const YamlReader& yr, const YAML::Node& root, long long seed_override, Scenario& s) {
  s.dt = yr.get<double>(root, "dt", "", s.dt);
  if (s.dt <= 0.0 || s.dt > 0.1) yr.fail(root["dt"], "dt", "must be in (0, 0.1] s");
  s.time_limit = yr.get<double>(root, "time_limit", "", s.time_limit);
  if (s.time_limit <= 0.0 || s.time_limit > kMaxTimeLimit)
    yr.fail(root["time_limit"], "time_limit", "must be in (0, 1e7] s");
  const long long seed = yr.get<long long>(root, "seed", "", 1);
  if (seed < 0) yr.fail(root["seed"], "seed", "must be >= 0");
  s.seed = static_cast<std::uint64_t>(seed_override >= 0 ? seed_override : seed);
  s.obstacle_radius = yr.get<double>(root, "obstacle_radius", "", s.obstacle_radius);
  // The world's obstacle grid reaches this far beyond the map.
  if (s.obstacle_radius <= 0.0 || s.obstacle_radius > 1e3)
    yr.fail(root["obstacle_radius"], "obstacle_radius", "must be in (0, 1e3] m");
  s.stuck_timeout = yr.get<double>(root, "stuck_timeout", "", s.stuck_timeout);
  if (s.stuck_timeout < 0.0 || s.stuck_timeout > kMaxTimeLimit)
    yr.fail(root["stuck_timeout"], "stuck_timeout", "must be in [0, 1e7] s (0: never)");
  s.stuck_distance = yr.get<double>(root, "stuck_distance", "", s.stuck_distance);
  if (s.stuck_distance <= 0.0 || s.stuck_distance > 1e3)
    yr.fail(root["stuck_distance"], "stuck_distance", "must be in (0, 1e3] m");
}

void readEvaluation(const YamlReader& yr, const YAML::Node& root, const std::string& path, Scenario& s) {
  if (const YAML::Node evaluation = yr.child(root, "evaluation", "", false)) {
    s.evaluation_sample_rate = yr.get<double>(evaluation, "sample_rate", "evaluation", 0.0);
    // The evaluator's own bounds (sample_rate.hpp), checked here so that a bad value stops the run
    // before anything starts.
    const double r = s.evaluation_sample_rate;
    if (r != 0.0 && !(r >= 1e-6 && r <= 1e6))
      yr.fail(evaluation["sample_rate"], "evaluation.sample_rate", "must be 0 (every tick) or between 1e-6 and 1e6 Hz");
    s.evaluation_metrics = readMetricsPath(yr, evaluation, path);
  }
}

// `people`: a HuNavSim agents file, or the agents (and the people model) in the scenario itself.
void readPeople(const YamlReader& yr, const YAML::Node& root, const std::string& path, Scenario& s) {
  if (const YAML::Node people = yr.child(root, "people", "", false)) {
    if (people.IsScalar()) {  // a HuNavSim agents file, relative to the scenario
      std::filesystem::path p = people.Scalar();
      if (p.is_relative()) p = std::filesystem::path(path).parent_path() / p;
      std::error_code ec;
      if (!std::filesystem::exists(p, ec)) yr.fail(people, "people", "cannot open the file '" + p.string() + "'");
      if (!std::filesystem::is_regular_file(p, ec))
        yr.fail(people, "people", "'" + p.string() + "' is not a regular file");
      s.agents = loadAgentsFile(p.string(), s.seed, &s.global_goals);
    } else {
      s.agents = parseAgents(yr, people, "people", s.seed, s.shapes, &s.global_goals);
      readPeopleModel(yr, people, s.people_model);
    }
  }
}

// The robot's start and goal and every agent's start clear of the walls; the robot's id its own.
void checkStartsAndIds(const YamlReader& yr, const YAML::Node& root, const std::string& path, const Scenario& s) {
  const YAML::Node robot = root["robot"];
  checkClear(yr, s, robot["start"], "robot.start", s.robot.start, s.robot.radius, "the robot start");
  if (s.robot.has_goal) checkClear(yr, s, robot["goal"], "robot.goal", s.robot.goal, s.robot.radius, "the robot goal");
  for (const AgentConfig& a : s.agents) {
    if (a.id == s.robot.id)
      throw ConfigError(path, YamlReader::lineOf(robot["id"]), "robot.id", "the robot id is used by agent " + a.name);
    for (const Shape& sh : s.shapes)
      if (sh.distance(a.position) < a.radius)
        throw ConfigError(a.source_file, a.source_line, a.name + ".init_pose",
                          "the agent starts inside or touching a wall");
  }
}

}  // namespace

void overridePeopleModel(Scenario& s, const std::string& name_or_file) {
  s.people_model.model = resolveMotionModel(name_or_file, "", "", 0, "--people-model");
  for (AgentConfig& a : s.agents) a.people_model.reset();
}

std::string peopleModelLabel(const Scenario& s) {
  std::set<std::string> names;
  for (const AgentConfig& a : s.agents) names.insert(a.people_model ? a.people_model->name : s.people_model.model.name);
  if (names.empty()) names.insert(s.people_model.model.name);
  std::string label;
  for (const std::string& n : names) label += (label.empty() ? "" : "+") + n;
  for (char& c : label)
    if (c == ',' || c == '\n' || c == '"') c = ';';  // a CSV field of its own
  return names.size() == 1 ? label : "mixed:" + label;
}

Scenario loadScenario(const std::string& path, long long seed_override) {
  YamlReader yr(path);
  const YAML::Node& root = yr.root();
  Scenario s;
  s.file = path;
  readScenarioName(yr, root, path, s);
  readSimulationSettings(yr, root, seed_override, s);
  readEvaluation(yr, root, path, s);

  if (const YAML::Node expect = yr.child(root, "expect", "", false)) s.expectations = readExpectations(yr, expect);

  if (const YAML::Node map = yr.child(root, "map", "", false)) readMap(yr, map, s);
  readRobot(yr, yr.child(root, "robot", "", true), s.robot);
  if (!yr.child(root, "stuck_timeout", "", false)) s.stuck_timeout = defaultStuckTimeout(s.robot);
  readPeople(yr, root, path, s);
  checkStartsAndIds(yr, root, path, s);
  return s;
}

}  // namespace hunav
