#pragma once
// A bus that loses each outgoing message with a given probability (seeded, reproducible), to prove
// that the step protocol survives loss: wrap the bus the components share and hand them this.
#include <cstdint>

#include "hunav/bus_backend.hpp"

namespace hunav::testing {

class LossyBus final : public ForwardingBus {
 public:
  LossyBus(Bus& inner, double probability, std::uint64_t seed)
      : ForwardingBus(inner), probability_(probability), state_(seed) {}

  void publishRaw(std::string_view channel, const void* data, std::size_t size) override {
    if (!loseNext()) ForwardingBus::publishRaw(channel, data, size);
  }
  void setLossProbability(double probability) { probability_ = probability; }
  std::uint64_t lost() const { return lost_; }

 private:
  void publishMessage(std::string_view channel, const OutgoingMessage& msg) override {
    if (!loseNext()) ForwardingBus::publishMessage(channel, msg);
  }
  bool loseNext() {
    // splitmix64: a tiny reproducible generator.
    state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    if (static_cast<double>(z >> 11) * 0x1.0p-53 >= probability_) return false;
    ++lost_;
    return true;
  }

  double probability_;
  std::uint64_t state_;
  std::uint64_t lost_ = 0;
};

}  // namespace hunav::testing
