#pragma once
// What tests read from inside a bus backend and no product code may: the backends name this class
// their friend, so their test hooks stay out of their public interface.
#include <cstdint>

#include "hunav/udpm_bus.hpp"

namespace hunav::testing {

class TransportProbe {
 public:
  // Datagrams the sockets of `bus` read (those its socket filter dropped never count).
  static std::uint64_t datagramsRead(const UdpmBus& bus) { return bus.datagramsRead(); }
};

}  // namespace hunav::testing
