#pragma once
// What the templates of bus.hpp instantiate for each message type: a message held by a backend that
// does not know its type (the in-process queue), and a subscription's typed handler. Nothing here is
// for users of the bus; backends reach it through bus_backend.hpp.
#include <cstdint>
#include <exception>
#include <functional>
#include <hunav/wire_checks.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace hunav {

class BusBackend;
class Subscription;

namespace bus_detail {

template <class Msg>
void encodeMessage(const Msg& msg, std::vector<std::uint8_t>& out) {
  const int size = msg.getEncodedSize();
  out.resize(static_cast<std::size_t>(size));
  if (msg.encode(out.data(), 0, size) != size) throw std::runtime_error("cannot encode a message");
}

// Decodes `size` bytes into `msg` (a fresh one: see TypedSubscriber); false when they are not a
// Msg. lcm-gen's decoder trusts string lengths and array counts (a bad one crashes or allocates
// gigabytes): the bytes are checked first (lcmtypes/gen_wire_checks.py).
template <class Msg>
bool decodeChecked(const void* data, std::size_t size, Msg& msg) {
  if (!wire::safeToDecode<Msg>(data, static_cast<unsigned>(size))) return false;
  try {
    return msg.decode(data, 0, static_cast<int>(size)) >= 0;
  } catch (const std::exception&) {
    return false;
  }
}

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

template <class Msg>
OutgoingMessage outgoing(const Msg& msg) {
  OutgoingMessage out;
  out.type = &kMessageType<Msg>;
  out.message = &msg;
  return out;
}
template <class Msg>
OutgoingMessage givenUp(Msg& msg) {
  OutgoingMessage out = outgoing(msg);
  out.given_up = &msg;
  return out;
}
inline OutgoingMessage withEncoding(OutgoingMessage out, const void* data, std::size_t size) {
  out.encoded = data;
  out.encoded_size = size;
  return out;
}

// One subscription's handler, for either form a backend holds a message in. What it dropped and the
// bus it is subscribed through are the bus's to change (BusBackend), and read through Subscription.
class Subscriber : public std::enable_shared_from_this<Subscriber> {
 public:
  explicit Subscriber(std::string channel) : channel_(std::move(channel)) {}
  virtual ~Subscriber() = default;
  // Decodes the bytes and calls the handler; false when they do not decode as its type.
  virtual bool takeBytes(const void* data, std::size_t size) = 0;
  // Calls the handler with a boxed message; false when the box holds another type.
  virtual bool takeBox(const MessageBox& box) = 0;
  const std::string& channel() const { return channel_; }

 private:
  friend class hunav::BusBackend;
  friend class hunav::Subscription;
  const std::string channel_;
  std::uint64_t drop_count_ = 0;
  std::string last_drop_reason_;
  BusBackend* bus_ = nullptr;  // the bus it was subscribed through; null once it ends
};

template <class Msg>
class TypedSubscriber final : public Subscriber {
 public:
  template <class Handler>
  TypedSubscriber(std::string channel, Handler&& handler)
      : Subscriber(std::move(channel)), handler_(std::forward<Handler>(handler)) {}
  bool takeBytes(const void* data, std::size_t size) override {
    // A fresh message each time: LCM 1.3.1 leaves a primitive array untouched when its count is 0.
    Msg msg;
    if (!decodeChecked(data, size, msg)) return false;
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

// A subscription to a channel's encoded bytes (Bus::subscribeEncoded): never decodes. A boxed
// message (the in-process bus) is not taken, so the backend hands over its encoding instead.
class EncodedSubscriber final : public Subscriber {
 public:
  using Handler = std::function<void(const std::uint8_t* data, std::size_t size)>;
  EncodedSubscriber(std::string channel, Handler handler)
      : Subscriber(std::move(channel)), handler_(std::move(handler)) {}
  bool takeBytes(const void* data, std::size_t size) override {
    handler_(static_cast<const std::uint8_t*>(data), size);
    return true;
  }
  bool takeBox(const MessageBox&) override { return false; }

 private:
  Handler handler_;
};

template <class Msg, class Handler>
std::shared_ptr<Subscriber> newSubscriber(std::string channel, Handler&& handler) {
  return std::make_shared<TypedSubscriber<Msg>>(std::move(channel), std::forward<Handler>(handler));
}

}  // namespace bus_detail
}  // namespace hunav
