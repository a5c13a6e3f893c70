#pragma once
// ETH/UCY pedestrian tracks: `frame id x y` per line (whitespace separated, metres), frames a fixed
// step apart (10 in the standard files). Malformed rows are ConfigErrors naming file, line and key.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "hunav/geometry.hpp"

namespace hunav::realism {

struct Dataset {
  std::string name;  // ETH, Hotel, Zara1, Zara2, Univ, or the file's stem
  std::string path;
  double frame_interval = 0.4;  // s between two consecutive annotated frames
  std::int64_t frame_step = 0;  // difference of two consecutive frame numbers (smallest one seen)
  // frame index ((frame number - first frame number) / frame_step) -> id -> position.
  std::map<std::int64_t, std::map<int, Vec2>> frames;
  std::size_t rows = 0;
  std::size_t people = 0;
};

// Reads a track file. Throws ConfigError(file, line, key, what) for a row that is not four finite
// numbers (NaN and infinities included), a frame or id that is not an integer, a frame smaller than
// the row before's, a repeated (frame, id), a frame number that is not a multiple of the step, or a
// file that cannot be opened or has no rows.
Dataset readTracks(const std::string& path);

// The common name of a standard file (biwi_eth -> ETH, biwi_hotel -> Hotel, crowds_zara01 -> Zara1,
// crowds_zara02 -> Zara2, students003 -> Univ), else the file's stem.
std::string datasetName(const std::string& path);
// The seconds per annotated frame of a standard file: 0.4 (2.5 Hz), except biwi_eth, re-sampled from
// a 6-frame annotation interval: 1/1.5 s (the data's SOURCE.md; 0.4 s would make them walk 2.3 m/s).
double defaultFrameInterval(const std::string& path);

}  // namespace hunav::realism
