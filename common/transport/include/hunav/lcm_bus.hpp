#pragma once
// The bus over liblcm, on any LCM URL: udpm:// between processes (channel_ports=1 opens one LCM
// instance per port, open_bus.hpp), memq:// in one process, or an LCM instance the caller owns (a
// log file being read). Messages are encoded; LCM's reader thread receives them and handleFor()
// dispatches them in the calling thread.
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <vector>

#include "hunav/bus_backend.hpp"

namespace hunav {

class LcmBus final : public BusBackend {
 public:
  // Over LCM instances of its own on `url`. Throws when LCM cannot be opened (bad URL, no route).
  explicit LcmBus(const std::string& url);
  // Over an LCM instance the caller owns (it must outlive the bus).
  explicit LcmBus(lcm::LCM& lcm);
  ~LcmBus() override;

  void publishRaw(std::string_view channel, const void* data, std::size_t size) override;
  bool handleFor(std::chrono::milliseconds timeout) override;

 private:
  void publishMessage(std::string_view channel, const OutgoingMessage& msg) override;
  void attach(Subscriber& sub, int queue_capacity) override;
  void detach(Subscriber& sub) override;

  struct Instances;
  void deliverFromLcm(Subscriber& sub, const lcm::ReceiveBuffer& rbuf);
  std::unique_ptr<Instances> lcm_;
  std::vector<std::uint8_t> buffer_;
};

}  // namespace hunav
