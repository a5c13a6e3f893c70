#pragma once
// The bus of a run in one process: a queue inside this object, dispatched in the thread that calls
// handleFor(). A message published as a typed object reaches subscribers of its type as a copy of
// that object (or the object itself, when given up), without encoding or decoding: LCM types
// round-trip exactly (every field is encoded, arrays as long as their count fields), so handlers
// see what decoding would give them and runs keep the fingerprints of a run over LCM. Bytes
// (publishRaw) are decoded as over LCM. Single-threaded: nothing arrives while handleFor() waits.
#include <memory>

#include "hunav/bus_backend.hpp"

namespace hunav {

class InProcessBus final : public BusBackend {
 public:
  InProcessBus();
  ~InProcessBus() override;

  void publishRaw(std::string_view channel, const void* data, std::size_t size) override;
  bool handleFor(std::chrono::milliseconds timeout) override;

 private:
  void publishMessage(std::string_view channel, const OutgoingMessage& msg) override;
  void attach(Subscriber& sub, int queue_capacity) override;
  void detach(Subscriber& sub) override;

  struct Queue;
  std::unique_ptr<Queue> queue_;
};

}  // namespace hunav
