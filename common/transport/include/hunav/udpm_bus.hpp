#pragma once
// The bus over LCM's UDP multicast (udpm://) with receive sockets of our own, read in the thread that
// calls handleFor(): LCM 1.3.1 receives each datagram on a reader thread per instance and hands it
// over through a pipe (several system calls and two context switches per message), which makes a
// lockstep tick cost several times the CPU (LcmBus; docs/performance.md, "Bus backends").
// Publishing goes through liblcm. The sockets speak LCM's wire format (whole messages and fragments
// of long ones), so LCM publishers, lcm-logger and lcm-spy interoperate with it. With channel_ports=1 (open_bus.hpp)
// each step channel has a port (and a socket) of its own.
// Nothing is lost while the caller keeps calling handleFor(): each wake-up reads every datagram
// waiting into the bus's queue, and while that queue holds a backlog the sockets are read again
// every kBacklogDrainMessages messages and every kBacklogDrainPeriod, so a socket buffer (the URL's
// recv_buf_size) only has to hold what arrives during one handler call. What is lost all the same
// is counted: receiveLosses().
#include <memory>
#include <string>

#include "hunav/bus_backend.hpp"
#include "hunav/open_bus.hpp"

namespace hunav {

namespace testing {
class TransportProbe;  // tests/support/hunav/testing/transport_probe.hpp
}

class UdpmBus final : public BusBackend {
 public:
  static constexpr int kBacklogDrainMessages = 8;
  static constexpr std::chrono::milliseconds kBacklogDrainPeriod{1};

  // Throws when LCM cannot be opened on `url` (bad URL, no multicast route).
  explicit UdpmBus(const std::string& url, const ReceiveOptions& options = {});
  ~UdpmBus() override;

  void publishRaw(std::string_view channel, const void* data, std::size_t size) override;
  bool handleFor(std::chrono::milliseconds timeout) override;
  std::uint64_t droppedMessages() const override;
  std::uint64_t malformedDatagrams() const override;
  ReceiveLosses receiveLosses() const override;
  bool sampleChannel(std::string_view channel, std::uint32_t every) override;

 private:
  friend class testing::TransportProbe;
  void publishMessage(std::string_view channel, const OutgoingMessage& msg) override;
  void attach(Subscriber& sub, int queue_capacity) override;
  void detach(Subscriber& sub) override;
  // Datagrams the sockets read (those a socket filter dropped never count): for tests.
  std::uint64_t datagramsRead() const;

  struct Ports;
  std::unique_ptr<Ports> ports_;
};

}  // namespace hunav
