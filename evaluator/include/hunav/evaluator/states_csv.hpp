#pragma once
// states.csv (DESIGN.md section 10): one row per entity per recorded tick, robot row first.
//   t,kind,id,x,y,yaw,vx,vy,vyaw,linear_vel,angular_vel,radius,behavior,behavior_state,group,
//   goal_x,goal_y,goal_radius,obs
// Numbers are written with the shortest representation that reads back as the same double, so
// readStatesCsv() rebuilds the Recording the live evaluator had, bit for bit.
#include "hunav/evaluator/recording.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace hunav::evaluator {

inline constexpr const char* kStatesCsvHeader =
    "t,kind,id,x,y,yaw,vx,vy,vyaw,linear_vel,angular_vel,radius,behavior,behavior_state,group,goal_x,goal_y,"
    "goal_radius,obs";

class StatesCsvWriter {
 public:
  // Creates (truncates) the file and writes the header. Throws std::runtime_error on I/O errors.
  explicit StatesCsvWriter(const std::filesystem::path& file);
  ~StatesCsvWriter();
  StatesCsvWriter(const StatesCsvWriter&) = delete;
  StatesCsvWriter& operator=(const StatesCsvWriter&) = delete;

  // Writes the rows of sample `s` of `r` (robot first, then agents) and flushes them to the OS, so
  // a killed evaluator leaves every recorded tick on disk.
  void write(const Recording& r, const Sample& s);
  void close();
  const std::filesystem::path& path() const { return path_; }

 private:
  void appendRow(const Recording& r, double t, const char* kind, const EntityState& e);

  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  fmt::memory_buffer buffer_;
};

// Reads a states.csv back into a Recording. Throws ConfigError naming file, line and column on a
// malformed file (wrong header or field count, bad number, agent row without a robot row, time not
// increasing, incomplete goal columns, bad obs list).
Recording readStatesCsv(const std::filesystem::path& file);

}  // namespace hunav::evaluator
