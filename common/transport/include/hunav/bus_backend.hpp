#pragma once
// For writing a bus backend (in_process_bus.hpp, lcm_bus.hpp, udpm_bus.hpp) or a decorator of a bus
// (ForwardingBus below: recording a log, losing messages in tests). Users of a bus need only
// bus.hpp. A backend implements publishMessage, publishRaw, handleFor, attach and detach, delivers
// each message it receives to its subscribers with deliver(), calls rethrowPending() after a
// dispatch and endEverySubscription() first in its destructor.
#include <chrono>
#include <cstdint>
#include <exception>
#include <memory>
#include <string_view>
#include <vector>

#include "hunav/bus.hpp"

namespace hunav {

using bus_detail::MessageBox;
using bus_detail::MessageType;
using bus_detail::OutgoingMessage;
using bus_detail::Subscriber;

class BusBackend : public Bus {
 public:
  std::uint64_t droppedMessages() const override { return dropped_; }

 protected:
  BusBackend() = default;
  // A backend has ended its subscriptions already (endEverySubscription()); whatever is left only
  // loses its bus.
  ~BusBackend() override;

  // --- What each backend implements (and a decorator forwards) ---
  void publishMessage(std::string_view channel, const OutgoingMessage& msg) override = 0;
  // Starts and ends delivering to `sub` on sub.channel().
  virtual void attach(Subscriber& sub, int queue_capacity) = 0;
  virtual void detach(Subscriber& sub) = 0;

  // Calls `sub`'s handler: an undecodable message or a BadMessage is counted, any other exception
  // kept for rethrowPending(). A subscription ended meanwhile is skipped.
  void deliver(Subscriber& sub, const void* data, std::size_t size);
  void deliver(Subscriber& sub, const MessageBox& box);
  void rethrowPending();
  void countDrop() { ++dropped_; }
  // Backends and decorators call this first in their destructors: every live subscription ends.
  void endEverySubscription();

 private:
  friend class Subscription;   // ends its subscriber (end())
  friend class ForwardingBus;  // forwards to the protected members of the bus it decorates

  Subscription subscribeWith(std::shared_ptr<Subscriber> sub, int queue_capacity) final;
  // Ends `sub` (what Subscription::reset does).
  void end(Subscriber& sub);
  // Runs take() (false: the message does not decode) for a live subscriber, counting drops.
  template <class Take>
  void guardedCall(Subscriber& sub, Take&& take);

  std::vector<std::shared_ptr<Subscriber>> subscribers_;
  std::exception_ptr pending_;
  std::uint64_t dropped_ = 0;
  std::vector<std::uint8_t> convert_buffer_;  // a box encoded for a subscriber of another type
};

// Forwards everything to another bus: the base of decorators, which override what they change.
// The inner bus must outlive it.
class ForwardingBus : public BusBackend {
 public:
  // Every Bus is a BusBackend (Bus has no other derived class).
  explicit ForwardingBus(Bus& inner) : inner_(static_cast<BusBackend&>(inner)) {}
  ~ForwardingBus() override { endEverySubscription(); }

  void publishRaw(std::string_view channel, const void* data, std::size_t size) override {
    inner_.publishRaw(channel, data, size);
  }
  bool handleFor(std::chrono::milliseconds timeout) override { return inner_.handleFor(timeout); }
  std::uint64_t droppedMessages() const override { return inner_.droppedMessages(); }
  std::uint64_t malformedDatagrams() const override { return inner_.malformedDatagrams(); }
  ReceiveLosses receiveLosses() const override { return inner_.receiveLosses(); }

 protected:
  void publishMessage(std::string_view channel, const OutgoingMessage& msg) override {
    inner_.publishMessage(channel, msg);
  }
  void attach(Subscriber& sub, int queue_capacity) override { inner_.attach(sub, queue_capacity); }
  void detach(Subscriber& sub) override { inner_.detach(sub); }
  Bus& inner() { return inner_; }

 private:
  BusBackend& inner_;
};

}  // namespace hunav
