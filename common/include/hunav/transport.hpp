#pragma once
// A small typed layer over lcm::LCM, shared by every process.
//  - subscribe() takes any callable; every subscription gets a queue capacity (unbounded by default,
//    because LCM's default of 30 silently drops the newest messages).
//  - A message that does not decode, or whose handler throws BadMessage, is dropped and counted.
//  - Any other exception thrown by a handler is caught before it crosses LCM's C code and rethrown
//    from handle*() to the caller.
// Two backends with the same semantics (FIFO, one message per handle, encoded bytes):
//  - over an lcm::LCM (any URL: udpm between processes, memq:// in one process);
//  - in-process (Bus::InProcess): a plain queue in this object, for the one-process runner. It is
//    memq:// without the pipe write, select and read that memq costs per message (a third of an
//    in-process tick), so the messages, and the fingerprints, are exactly those of an LCM run.
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace hunav {

// Default bus: UDP multicast that never leaves this host (ttl=0), with a receive buffer large enough
// for world states of big crowds.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

// URL precedence: the --lcm-url flag, then LCM_DEFAULT_URL, then kDefaultLcmUrl.
std::string resolveLcmUrl(const std::string& flag_value);

// Thrown by a handler that rejects a message it cannot use (NaN, impossible sizes, unknown ids).
struct BadMessage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Bus {
 public:
  static constexpr int kUnbounded = 0;

  explicit Bus(lcm::LCM& lcm);
  struct InProcess {};
  explicit Bus(InProcess);
  ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  template <class Msg, class Handler>
  void subscribe(const std::string& channel, Handler&& handler, int queue_capacity = kUnbounded) {
    auto sub = std::make_unique<TypedSubscription<Msg>>(this, std::function<void(const Msg&)>(
                                                                  std::forward<Handler>(handler)));
    attach(channel, std::move(sub), queue_capacity);
  }

  template <class Msg>
  void publish(const std::string& channel, const Msg& msg) {
    const int size = msg.getEncodedSize();
    buffer_.resize(static_cast<std::size_t>(size));
    if (msg.encode(buffer_.data(), 0, size) != size) throw std::runtime_error("cannot encode a message for " + channel);
    publishRaw(channel, buffer_.data(), buffer_.size());
  }

  // Encodes into an internal buffer and returns it (valid until the next encode/publish).
  template <class Msg>
  const std::vector<std::uint8_t>& encode(const Msg& msg) {
    const int size = msg.getEncodedSize();
    buffer_.resize(static_cast<std::size_t>(size));
    msg.encode(buffer_.data(), 0, size);
    return buffer_;
  }

  void publishRaw(const std::string& channel, const void* data, std::size_t size);

  // Waits up to `timeout` for one message and dispatches it. Returns false on timeout.
  bool handleFor(std::chrono::milliseconds timeout);
  // Dispatches every message already waiting, without blocking.
  void handleAvailable();

  std::uint64_t droppedMessages() const { return dropped_; }
  bool inProcess() const { return lcm_ == nullptr; }

  // Sees every message published through this bus (for recording a log of an in-process run).
  using Tap = std::function<void(const std::string& channel, const void* data, std::size_t size)>;
  void setTap(Tap tap) { tap_ = std::move(tap); }

  // Test hook: drop each outgoing message with this probability (seeded, reproducible), to prove the
  // protocol survives loss. 0 disables it.
  void setOutgoingLossForTesting(double probability, std::uint64_t seed);
  std::uint64_t lostForTesting() const { return lost_for_testing_; }

 private:
  struct Subscription {
    virtual ~Subscription() = default;
    void onRaw(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
    void deliver(const void* data, unsigned size);
    virtual void dispatch(const void* data, unsigned size) = 0;
    Bus* bus = nullptr;
    lcm::Subscription* handle = nullptr;  // LCM backend
    std::string channel;                  // in-process backend (exact channel names)
  };
  struct Queued {
    std::string channel;
    std::vector<std::uint8_t> data;
  };
  template <class Msg>
  struct TypedSubscription : Subscription {
    TypedSubscription(Bus* b, std::function<void(const Msg&)> h) : handler(std::move(h)) { bus = b; }
    void dispatch(const void* data, unsigned size) override {
      Msg msg;
      int decoded = -1;
      try {  // generated decoders throw (length_error, bad_alloc) on absurd array counts
        decoded = msg.decode(data, 0, static_cast<int>(size));
      } catch (const std::exception&) {
        decoded = -1;
      }
      if (decoded < 0) {
        ++bus->dropped_;
        return;
      }
      handler(msg);
    }
    std::function<void(const Msg&)> handler;
  };

  void attach(const std::string& channel, std::unique_ptr<Subscription> sub, int queue_capacity);
  void rethrowPending();

  lcm::LCM* lcm_ = nullptr;  // null: in-process backend
  std::deque<Queued> queue_;
  std::vector<std::vector<std::uint8_t>> spare_buffers_;  // recycled, so queuing does not allocate
  Tap tap_;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;
  std::vector<std::uint8_t> buffer_;
  std::exception_ptr pending_;
  std::uint64_t dropped_ = 0;
  double loss_probability_ = 0.0;
  std::uint64_t loss_state_ = 0;
  std::uint64_t lost_for_testing_ = 0;
};

}  // namespace hunav
