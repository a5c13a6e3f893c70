#pragma once
// The message bus every process talks through: publish LCM messages on named channels, subscribe
// handlers, and dispatch what arrived in the calling thread with handleFor(). One interface, one
// backend per file:
//  - InProcessBus (in_process_bus.hpp): a queue inside the object, for the one-process runner;
//    typed messages reach subscribers as copies, never encoded.
//  - LcmBus (lcm_bus.hpp): liblcm on any LCM URL (udpm://, memq://, a log file).
//  - UdpmBus (udpm_bus.hpp): udpm through receive sockets of our own, read in the calling thread.
// openBus() (open_bus.hpp) picks one for a URL; ForwardingBus (below) is the base of decorators
// (recording a log, losing messages in tests). What every backend guarantees:
//  - one FIFO over all channels; each handleFor() dispatches at most one message;
//  - a message that does not decode as the subscription's type, or whose handler throws
//    BadMessage, is dropped and counted (droppedMessages(), Subscription::drops());
//  - any other exception a handler throws is rethrown from handleFor() to its caller;
//  - a handler runs until its Subscription is destroyed or reset();
//  - publish(channel, std::move(msg)) may take the message's contents: msg is left valid with
//    unspecified contents (assign every field before using it again), on every backend.
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <hunav/wire_checks.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace hunav {

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

// A message of an LCM type held by a backend that does not know the type (the in-process queue).
class MessageBox {
 public:
  virtual ~MessageBox() = default;
  virtual const void* typeTag() const = 0;
  virtual void encodeTo(std::vector<std::uint8_t>& out) const = 0;
};

// What a backend may do with a message of a type it does not know.
struct MessageType {
  void (*encode)(const void* msg, std::vector<std::uint8_t>& out);
  std::unique_ptr<MessageBox> (*new_box)();
  void (*copy_into)(MessageBox& box, const void* msg);
  void (*swap_into)(MessageBox& box, void* msg);  // the caller gets the box's previous message
};

template <class Msg>
void encodeMessage(const Msg& msg, std::vector<std::uint8_t>& out) {
  const int size = msg.getEncodedSize();
  out.resize(static_cast<std::size_t>(size));
  if (msg.encode(out.data(), 0, size) != size) throw std::runtime_error("cannot encode a message");
}

template <class Msg>
class TypedMessageBox;

// The operations for Msg; its address also identifies the type.
template <class Msg>
inline const MessageType kMessageType = {
    [](const void* msg, std::vector<std::uint8_t>& out) { encodeMessage(*static_cast<const Msg*>(msg), out); },
    []() -> std::unique_ptr<MessageBox> { return std::make_unique<TypedMessageBox<Msg>>(); },
    [](MessageBox& box, const void* msg) {
      static_cast<TypedMessageBox<Msg>&>(box).msg = *static_cast<const Msg*>(msg);
    },
    [](MessageBox& box, void* msg) {
      using std::swap;
      swap(static_cast<TypedMessageBox<Msg>&>(box).msg, *static_cast<Msg*>(msg));
    }};

template <class Msg>
class TypedMessageBox final : public MessageBox {
 public:
  const void* typeTag() const override { return &kMessageType<Msg>; }
  void encodeTo(std::vector<std::uint8_t>& out) const override { encodeMessage(msg, out); }
  Msg msg;
};

// A message being published: the object, its type's operations, and its encoding if the caller
// already has it.
struct OutgoingMessage {
  const MessageType* type = nullptr;
  const void* message = nullptr;
  void* given_up = nullptr;  // the same object, when the caller gave it up (std::move)
  const void* encoded = nullptr;
  std::size_t encoded_size = 0;
};

class Bus;

// One subscription's handler, for either form a backend holds a message in.
class Subscriber : public std::enable_shared_from_this<Subscriber> {
 public:
  explicit Subscriber(std::string channel_name) : channel(std::move(channel_name)) {}
  virtual ~Subscriber() = default;
  // Decodes the bytes and calls the handler; false when they do not decode as its type.
  virtual bool takeBytes(const void* data, std::size_t size) = 0;
  // Calls the handler with a boxed message; false when the box holds another type.
  virtual bool takeBox(const MessageBox& box) = 0;

  const std::string channel;
  SubscriptionDrops drops;
  Bus* bus = nullptr;  // the bus it was subscribed through; null once it ends
};

// Ends a subscription when destroyed (or reset): its handler is not called again, not even for
// messages already queued. Movable; the bus may be destroyed first.
class [[nodiscard]] Subscription {
 public:
  Subscription() = default;
  explicit Subscription(std::shared_ptr<Subscriber> subscriber) : subscriber_(std::move(subscriber)) {}
  Subscription(Subscription&& other) noexcept = default;
  Subscription& operator=(Subscription&& other) noexcept;
  Subscription(const Subscription&) = delete;
  Subscription& operator=(const Subscription&) = delete;
  ~Subscription() { reset(); }

  void reset();
  // What this subscription dropped (a component sharing a bus with others can tell its own).
  const SubscriptionDrops& drops() const;
  bool active() const { return subscriber_ && subscriber_->bus != nullptr; }

 private:
  std::shared_ptr<Subscriber> subscriber_;
};

class Bus {
 public:
  static constexpr int kUnbounded = 0;

  Bus() = default;
  virtual ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  // Calls `handler` with each message of type Msg on `channel`. A queue capacity bounds how many
  // may wait (LcmBus; the other backends never hold more than the protocol has in flight).
  template <class Msg, class Handler>
  Subscription subscribe(std::string_view channel, Handler&& handler, int queue_capacity = kUnbounded) {
    auto sub = std::make_shared<TypedSubscriber<Msg>>(std::string(channel), std::forward<Handler>(handler));
    return add(std::move(sub), queue_capacity);
  }

  template <class Msg>
  void publish(std::string_view channel, const Msg& msg) {
    OutgoingMessage out;
    out.type = &kMessageType<Msg>;
    out.message = &msg;
    publishMessage(channel, out);
  }
  // The same for a message the caller gives up: the bus may take its contents (see the top).
  template <class Msg, class = std::enable_if_t<!std::is_lvalue_reference_v<Msg>>>
  void publish(std::string_view channel, Msg&& msg) {
    OutgoingMessage out;
    out.type = &kMessageType<Msg>;
    out.message = &msg;
    out.given_up = &msg;
    publishMessage(channel, out);
  }
  // Publishes `msg` whose encoding the caller already has (from encode(), to hash it).
  template <class Msg>
  void publishEncoded(std::string_view channel, const Msg& msg, const void* data, std::size_t size) {
    OutgoingMessage out;
    out.type = &kMessageType<Msg>;
    out.message = &msg;
    out.encoded = data;
    out.encoded_size = size;
    publishMessage(channel, out);
  }
  template <class Msg, class = std::enable_if_t<!std::is_lvalue_reference_v<Msg>>>
  void publishEncoded(std::string_view channel, Msg&& msg, const void* data, std::size_t size) {
    OutgoingMessage out;
    out.type = &kMessageType<Msg>;
    out.message = &msg;
    out.given_up = &msg;
    out.encoded = data;
    out.encoded_size = size;
    publishMessage(channel, out);
  }
  // Encodes into a buffer of this bus and returns it (valid until the next encode()).
  template <class Msg>
  const std::vector<std::uint8_t>& encode(const Msg& msg) {
    encodeMessage(msg, encode_buffer_);
    return encode_buffer_;
  }

  // Dispatches every message already waiting, without blocking.
  void handleAvailable();

  // --- What each backend implements (and a decorator forwards) ---
  virtual void publishMessage(std::string_view channel, const OutgoingMessage& msg) = 0;
  // Publishes encoded bytes; subscribers decode them (a message that does not decode is dropped).
  virtual void publishRaw(std::string_view channel, const void* data, std::size_t size) = 0;
  // Waits up to `timeout` for one message and dispatches it. False on timeout or a signal (EINTR).
  virtual bool handleFor(std::chrono::milliseconds timeout) = 0;
  // Messages dropped: undecodable, rejected by a handler, or datagrams not in LCM's format.
  virtual std::uint64_t droppedMessages() const { return dropped_; }
  // Of those, datagrams not in LCM's format (a backend reading sockets itself; else 0).
  virtual std::uint64_t malformedDatagrams() const { return 0; }
  // What the backend's receive path lost so far (zeros when it cannot tell).
  virtual ReceiveLosses receiveLosses() const { return {}; }
  // Starts and ends delivering to `sub` on sub.channel (Subscription calls end()).
  virtual void attach(Subscriber& sub, int queue_capacity) = 0;
  virtual void detach(Subscriber& sub) = 0;

  // Ends `sub` (what Subscription::reset does).
  void end(Subscriber& sub);

 protected:
  // Calls `sub`'s handler: an undecodable message or a BadMessage is counted, any other exception
  // kept for rethrowPending(). A subscription ended meanwhile is skipped.
  void deliver(Subscriber& sub, const void* data, std::size_t size);
  void deliver(Subscriber& sub, const MessageBox& box);
  void rethrowPending();
  void countDrop() { ++dropped_; }
  // Backends and decorators call this first in their destructors: every live subscription ends.
  void endEverySubscription();

 private:
  template <class Msg>
  class TypedSubscriber final : public Subscriber {
   public:
    template <class Handler>
    TypedSubscriber(std::string channel_name, Handler&& handler)
        : Subscriber(std::move(channel_name)), handler_(std::forward<Handler>(handler)) {}
    bool takeBytes(const void* data, std::size_t size) override {
      // lcm-gen's decoder trusts string lengths and array counts (a bad one crashes or allocates
      // gigabytes): the bytes are checked first (lcmtypes/gen_wire_checks.py). A fresh message
      // each time: LCM 1.3.1 leaves a primitive array untouched when its count is 0.
      if (!wire::safeToDecode<Msg>(data, static_cast<unsigned>(size))) return false;
      Msg msg;
      int decoded = -1;
      try {
        decoded = msg.decode(data, 0, static_cast<int>(size));
      } catch (const std::exception&) {
        decoded = -1;
      }
      if (decoded < 0) return false;
      handler_(msg);
      return true;
    }
    bool takeBox(const MessageBox& box) override {
      if (box.typeTag() != &kMessageType<Msg>) return false;
      handler_(static_cast<const TypedMessageBox<Msg>&>(box).msg);
      return true;
    }

   private:
    std::function<void(const Msg&)> handler_;
  };

  Subscription add(std::shared_ptr<Subscriber> sub, int queue_capacity);
  // Runs take() (false: the message does not decode) for a live subscriber, counting drops.
  template <class Take>
  void guardedCall(Subscriber& sub, Take&& take);

  std::vector<std::shared_ptr<Subscriber>> subscribers_;
  std::exception_ptr pending_;
  std::uint64_t dropped_ = 0;
  std::vector<std::uint8_t> encode_buffer_;
  std::vector<std::uint8_t> convert_buffer_;  // a box encoded for a subscriber of another type
};

// Forwards everything to another bus: the base of decorators, which override what they change.
// The inner bus must outlive it.
class ForwardingBus : public Bus {
 public:
  explicit ForwardingBus(Bus& inner) : inner_(inner) {}
  ~ForwardingBus() override { endEverySubscription(); }

  void publishMessage(std::string_view channel, const OutgoingMessage& msg) override {
    inner_.publishMessage(channel, msg);
  }
  void publishRaw(std::string_view channel, const void* data, std::size_t size) override {
    inner_.publishRaw(channel, data, size);
  }
  bool handleFor(std::chrono::milliseconds timeout) override { return inner_.handleFor(timeout); }
  std::uint64_t droppedMessages() const override { return inner_.droppedMessages(); }
  std::uint64_t malformedDatagrams() const override { return inner_.malformedDatagrams(); }
  ReceiveLosses receiveLosses() const override { return inner_.receiveLosses(); }
  void attach(Subscriber& sub, int queue_capacity) override { inner_.attach(sub, queue_capacity); }
  void detach(Subscriber& sub) override { inner_.detach(sub); }

 protected:
  Bus& inner() { return inner_; }

 private:
  Bus& inner_;
};

}  // namespace hunav
