#pragma once
// states.csv (evaluator/README.md, "Files"): one row per entity per recorded tick, robot row first.
//   t,kind,id,x,y,yaw,vx,vy,vyaw,linear_vel,angular_vel,radius,behavior,behavior_state,group,
//   goal_x,goal_y,goal_radius,obs
// Numbers are written with the shortest representation that reads back as the same double, so
// reading the file rebuilds the samples the live evaluator had, bit for bit.
#include <fmt/format.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "hunav/results/number_text.hpp"
#include "hunav/results/recording.hpp"
#include "hunav/results/sample_rate.hpp"

namespace hunav::results {

inline constexpr const char* kStatesCsvHeader =
    "t,kind,id,x,y,yaw,vx,vy,vyaw,linear_vel,angular_vel,radius,behavior,behavior_state,group,goal_x,goal_y,"
    "goal_radius,obs";

class StatesCsvWriter {
 public:
  // Creates (truncates) the file and writes the header. Throws std::runtime_error on I/O errors.
  explicit StatesCsvWriter(const std::filesystem::path& file);
  // Flushes what is buffered (errors ignored: call close() to see them) and closes the file.
  ~StatesCsvWriter();
  StatesCsvWriter(const StatesCsvWriter&) = delete;
  StatesCsvWriter& operator=(const StatesCsvWriter&) = delete;

  // Formats the rows of sample `s` of `r` (robot first, then agents) into a buffer. The rows reach
  // the file at flush() or close(); the evaluator node decides when (evaluator_node.hpp).
  void write(const Recording& r, const Sample& s);
  // Hands the buffered rows to the OS (whole ticks only). Throws std::runtime_error on I/O errors.
  void flush();
  // Bytes and ticks formatted since the last flush.
  std::size_t bufferedBytes() const { return buffer_.size(); }
  std::size_t bufferedTicks() const { return buffered_ticks_; }
  // Flushes and closes; later writes throw std::logic_error.
  void close();
  const std::filesystem::path& path() const { return path_; }

 private:
  // The text of one entity's columns that rarely change, cached per entity: ",kind,id," and
  // "radius,behavior,behavior_state,group,goal_x,goal_y,goal_radius," with the values it was made
  // of (doubles compared bit for bit): while they stay the same a row copies the text.
  struct RowCache {
    bool has_head = false;
    std::int32_t id = 0;  // of `head` (the robot's may change)
    std::string head;     // ",kind,id,"
    bool has_tail = false;
    std::uint64_t radius = 0, goal_x = 0, goal_y = 0, goal_radius = 0;  // bits of the doubles
    std::int32_t group = 0;
    std::int8_t behavior = 0, behavior_state = 0;
    bool has_goal = false;
    std::string tail;  // "radius,...,goal_radius,"
  };
  // Agents with ids in [0, kCachedIds) have a RowCache; others are formatted in full.
  static constexpr std::int32_t kCachedIds = 1 << 16;
  RowCache* agentCache(std::int32_t id);
  void appendRow(const Recording& r, const char* kind, const EntityState& e, RowCache* cache);

  std::filesystem::path path_;
  std::FILE* file_ = nullptr;
  fmt::memory_buffer buffer_;
  fmt::memory_buffer time_text_;
  std::size_t buffered_ticks_ = 0;
  NumberText numbers_;
  RowCache robot_cache_;
  std::vector<RowCache> agent_caches_;  // by id, grown on demand
};

// Reads a states.csv sample by sample, in blocks (no per-line allocation). Errors throw ConfigError
// naming file, line and column: wrong header or field count, bad number, agent row without a robot
// row, time not increasing, incomplete goal columns, bad obs list. Every row is checked, also the
// rows of samples that the sample rate leaves out.
class StatesCsvReader {
 public:
  // Opens the file and checks the header. `rate` selects the samples to keep (SampleRate, every
  // sample by default).
  explicit StatesCsvReader(const std::filesystem::path& file, SampleRate rate = SampleRate());
  ~StatesCsvReader();
  StatesCsvReader(const StatesCsvReader&) = delete;
  StatesCsvReader& operator=(const StatesCsvReader&) = delete;

  // Appends the next kept samples to `into` until it received `max_samples` more (a sample is
  // complete when the next robot row or the end of the file is read). Returns false once the file
  // is exhausted (the samples of the last call are still appended).
  bool read(Recording& into, std::size_t max_samples);
  // Call before the first read(): also copy the header and the rows of the kept samples to `sink`
  // (line ends normalised to '\n', nothing else changed), in blocks, as they are read.
  void copyKeptRowsTo(std::FILE* sink);
  std::uintmax_t fileSize() const { return file_size_; }
  std::uintmax_t bytesRead() const { return bytes_read_; }

 private:
  bool nextLine(const char*& begin, const char*& end);
  void parseLine(const char* begin, const char* end);
  void commit(Recording& into);
  void copyText(const char* begin, std::size_t size);
  void flushCopy();

  std::filesystem::path file_;
  int fd_ = -1;
  std::uintmax_t file_size_ = 0;
  std::uintmax_t bytes_read_ = 0;
  SampleRate rate_;
  std::vector<char> block_;
  std::size_t block_begin_ = 0;  // unconsumed bytes are block_[block_begin_, block_end_)
  std::size_t block_end_ = 0;
  bool eof_ = false;
  int line_ = 0;  // of the line last read
  std::FILE* copy_ = nullptr;
  std::string copy_buffer_;

  // The sample being read.
  bool have_sample_ = false;
  bool keep_sample_ = false;
  double sample_t_ = 0.0;
  std::string sample_t_text_;
  bool any_robot_row_ = false;
  double previous_robot_t_ = 0.0;
  EntityState robot_;
  std::vector<EntityState> agents_;
  std::vector<Vec2> points_;  // obstacle points of robot_ and agents_ (offsets into this vector)
  std::vector<Vec2> row_points_;
};

// Reads a whole states.csv into a Recording (StatesCsvReader, every sample kept).
Recording readStatesCsv(const std::filesystem::path& file);

}  // namespace hunav::results
