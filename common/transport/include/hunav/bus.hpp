#pragma once
// The message bus every process talks through: publish LCM messages on named channels, subscribe
// handlers, and dispatch what arrived in the calling thread with handleFor(). One interface, one
// backend per file:
//  - InProcessBus (in_process_bus.hpp): a queue inside the object, for the one-process runner;
//    typed messages reach subscribers as copies, never encoded.
//  - LcmBus (lcm_bus.hpp): liblcm on any LCM URL (udpm://, memq://, a log file).
//  - UdpmBus (udpm_bus.hpp): udpm through receive sockets of our own, read in the calling thread.
// openBus() (open_bus.hpp) picks one for a URL. Writing a backend or a decorator (recording a log,
// losing messages in tests): bus_backend.hpp. What every backend guarantees:
//  - one FIFO over all channels; each handleFor() dispatches at most one message;
//  - a message that does not decode as the subscription's type, or whose handler throws
//    BadMessage, is dropped and counted (droppedMessages(), Subscription::drops());
//  - any other exception a handler throws is rethrown from handleFor() to its caller;
//  - a handler runs until its Subscription is destroyed or reset();
//  - publish(channel, std::move(msg)) may take the message's contents: msg is left valid with
//    unspecified contents (assign every field before using it again), on every backend.
#include <chrono>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "hunav/bus_detail.hpp"  // what the templates below instantiate (not for users)

namespace hunav {

// Decodes a message's bytes (from subscribeEncoded) into `msg`, a default-constructed one; false
// when they are not a Msg (checked before lcm-gen's decoder runs, as every subscription does).
template <class Msg>
bool decodeMessage(const void* data, std::size_t size, Msg& msg) {
  return bus_detail::decodeChecked(data, size, msg);
}

// Thrown by a handler that rejects a message it cannot use (NaN, impossible sizes, unknown ids).
struct BadMessage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What one subscription dropped: messages that did not decode as its type, or that its handler
// rejected (BadMessage).
struct SubscriptionDrops {
  std::uint64_t count = 0;
  std::string last_reason;  // why the last one was dropped
};

// Messages a backend's own receive path lost (zeros for a backend that cannot tell).
struct ReceiveLosses {
  std::uint64_t overflowed_datagrams = 0;  // the kernel dropped them: a receive buffer was full
  std::uint64_t incomplete_messages = 0;   // fragmented messages that lost a fragment
  bool any() const { return overflowed_datagrams != 0 || incomplete_messages != 0; }
};

// Ends a subscription when destroyed (or reset): its handler is not called again, not even for
// messages already queued. Movable; the bus may be destroyed first.
class [[nodiscard]] Subscription {
 public:
  Subscription() = default;
  Subscription(Subscription&& other) noexcept = default;
  Subscription& operator=(Subscription&& other) noexcept;
  Subscription(const Subscription&) = delete;
  Subscription& operator=(const Subscription&) = delete;
  ~Subscription() { reset(); }

  void reset();
  // What this subscription dropped so far (a component sharing a bus with others can tell its own).
  SubscriptionDrops drops() const;
  // drops().count without copying the reason: components sum it on every step.
  std::uint64_t droppedCount() const;
  bool active() const;

 private:
  friend class BusBackend;
  explicit Subscription(std::shared_ptr<bus_detail::Subscriber> subscriber) : subscriber_(std::move(subscriber)) {}
  std::shared_ptr<bus_detail::Subscriber> subscriber_;
};

class Bus {
 public:
  static constexpr int kUnbounded = 0;

  virtual ~Bus() = default;
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  // Calls `handler` with each message of type Msg on `channel`. A queue capacity bounds how many
  // may wait (LcmBus; the other backends never hold more than the protocol has in flight).
  template <class Msg, class Handler>
  Subscription subscribe(std::string_view channel, Handler&& handler, int queue_capacity = kUnbounded) {
    return subscribeWith(bus_detail::newSubscriber<Msg>(std::string(channel), std::forward<Handler>(handler)),
                         queue_capacity);
  }

  // Calls `handler` with the encoded bytes of each message on `channel`, undecoded (valid during the
  // call): for a monitor that keeps the newest and decodes only what it samples (decodeMessage()).
  // The in-process bus encodes its typed messages for it.
  Subscription subscribeEncoded(std::string_view channel, bus_detail::EncodedSubscriber::Handler handler,
                                int queue_capacity = kUnbounded) {
    return subscribeWith(std::make_shared<bus_detail::EncodedSubscriber>(std::string(channel), std::move(handler)),
                         queue_capacity);
  }

  template <class Msg>
  void publish(std::string_view channel, const Msg& msg) {
    publishMessage(channel, bus_detail::outgoing(msg));
  }
  // The same for a message the caller gives up: the bus may take its contents (see the top).
  template <class Msg, class = std::enable_if_t<!std::is_lvalue_reference_v<Msg>>>
  void publish(std::string_view channel, Msg&& msg) {
    publishMessage(channel, bus_detail::givenUp(msg));
  }
  // Publishes `msg` whose encoding the caller already has (from encode(), to hash it).
  template <class Msg>
  void publishEncoded(std::string_view channel, const Msg& msg, const void* data, std::size_t size) {
    publishMessage(channel, bus_detail::withEncoding(bus_detail::outgoing(msg), data, size));
  }
  template <class Msg, class = std::enable_if_t<!std::is_lvalue_reference_v<Msg>>>
  void publishEncoded(std::string_view channel, Msg&& msg, const void* data, std::size_t size) {
    publishMessage(channel, bus_detail::withEncoding(bus_detail::givenUp(msg), data, size));
  }
  // Publishes encoded bytes; subscribers decode them (a message that does not decode is dropped).
  virtual void publishRaw(std::string_view channel, const void* data, std::size_t size) = 0;
  // Encodes into a buffer of this bus and returns it (valid until the next encode()).
  template <class Msg>
  const std::vector<std::uint8_t>& encode(const Msg& msg) {
    bus_detail::encodeMessage(msg, encode_buffer_);
    return encode_buffer_;
  }

  // Waits up to `timeout` for one message and dispatches it. False on timeout or a signal (EINTR).
  virtual bool handleFor(std::chrono::milliseconds timeout) = 0;
  // Dispatches every message already waiting, without blocking.
  void handleAvailable();

  // Messages dropped: undecodable, rejected by a handler, or datagrams not in LCM's format.
  virtual std::uint64_t droppedMessages() const = 0;
  // Of those, datagrams not in LCM's format (a backend reading sockets itself; else 0).
  virtual std::uint64_t malformedDatagrams() const { return 0; }
  // What the backend's receive path lost so far (zeros when it cannot tell).
  virtual ReceiveLosses receiveLosses() const { return {}; }
  // Asks for only about one message in `every` of `channel` (1: all again), the others dropped
  // before they cost this process anything: for a watcher that shows a fraction of a fast channel
  // (hunav_view). True when the transport does it (UdpmBus with ReceiveOptions::
  // filter_unsubscribed_channels: its socket filter passes each message with probability 1/every);
  // false when every message keeps coming.
  virtual bool sampleChannel(std::string_view /*channel*/, std::uint32_t /*every*/) { return false; }

 private:
  friend class BusBackend;  // the one class derived from Bus, the base of every backend
  Bus() = default;
  virtual void publishMessage(std::string_view channel, const bus_detail::OutgoingMessage& msg) = 0;
  virtual Subscription subscribeWith(std::shared_ptr<bus_detail::Subscriber> sub, int queue_capacity) = 0;

  std::vector<std::uint8_t> encode_buffer_;
};

}  // namespace hunav
