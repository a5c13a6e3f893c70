#pragma once
// Numbers as the result files write them: the text fmt "{}" gives a double (the shortest text that
// reads back as the same double), produced faster. Formatting is most of the cost of writing
// states.csv and the per-tick files, and their values repeat a lot (radii, goals, flags, the robot's
// columns in every per-behavior file), so NumberText remembers recent texts.
#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>

namespace hunav::results {

// A double as every result file writes it: fmt "{}", the shortest text that reads back as the
// same double ("25.87", "3", "1e-07"). For one value; NumberText below for many.
std::string numberText(double v);

class NumberText {
 public:
  // Appends exactly what fmt::format("{}", v) gives.
  void append(fmt::memory_buffer& out, double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    Entry& e = entries_[(bits * 0x9E3779B97F4A7C15ull) >> (64 - kIndexBits)];
    if (e.size == 0 || e.bits != bits) {
      char* end = format(e.text, v);
      e.size = static_cast<std::uint8_t>(end - e.text);
      e.bits = bits;
    }
    // A copy of fixed size (a few vector moves, no call), then trimmed to the text.
    const std::size_t at = out.size();
    out.resize(at + sizeof e.text);
    std::memcpy(out.data() + at, e.text, sizeof e.text);
    out.resize(at + e.size);
  }

  // The text of `v` without the cache (what append() writes).
  static char* format(char* out, double v);

 private:
  static constexpr int kIndexBits = 9;
  struct Entry {
    std::uint64_t bits = 0;
    std::uint8_t size = 0;  // 0 = empty
    char text[31];          // the longest double text is 24 characters
  };
  std::array<Entry, std::size_t{1} << kIndexBits> entries_{};
};

}  // namespace hunav::results
