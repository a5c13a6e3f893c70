#pragma once
// --sample-rate HZ: recording and evaluating at a lower rate than the world's.
//
// The kept samples lie on a grid anchored at the first one, t_0: a sample is kept when it is the
// first at or after the next grid point t_0 + n/HZ (times compared in whole microseconds, as the
// world stamps them, so the live evaluator and a states.csv read back keep exactly the same ticks).
// A world tick that skips a grid point does not shift the grid. Applying the same rate to an already
// subsampled recording keeps every sample; rate 0 (the default) keeps every sample.
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace hunav::results {

class SampleRate {
 public:
  SampleRate() = default;
  // Throws std::invalid_argument unless hz is 0 or in [1e-6, 1e6].
  explicit SampleRate(double hz) : hz_(hz) {
    if (!(hz == 0.0 || (hz >= 1e-6 && hz <= 1e6)))
      throw std::invalid_argument("the sample rate must be 0 (every tick) or between 1e-6 and 1e6 Hz");
    if (hz > 0.0) period_us_ = std::llround(1e6 / hz);
  }
  double hz() const { return hz_; }
  bool everySample() const { return period_us_ == 0; }

  // Whether the sample at time t (s of simulation time, increasing from call to call) is kept.
  bool keep(double t) {
    const std::int64_t us = std::llround(t * 1e6);
    if (period_us_ == 0) return true;
    if (!started_) {
      started_ = true;
      first_us_ = us;
      next_us_ = first_us_ + period_us_;
      return true;
    }
    if (us < next_us_) return false;
    next_us_ = first_us_ + ((us - first_us_) / period_us_ + 1) * period_us_;
    return true;
  }

 private:
  double hz_ = 0.0;
  std::int64_t period_us_ = 0;
  bool started_ = false;
  std::int64_t first_us_ = 0;
  std::int64_t next_us_ = 0;
};

}  // namespace hunav::results
