#include "hunav/bus.hpp"

#include <algorithm>

#include "hunav/bus_backend.hpp"

namespace hunav {

namespace {
constexpr const char* kUndecodable = "a message that does not decode as the channel's type";
}

Subscription& Subscription::operator=(Subscription&& other) noexcept {
  if (this != &other) {
    reset();
    subscriber_ = std::move(other.subscriber_);
  }
  return *this;
}

void Subscription::reset() {
  if (subscriber_ && subscriber_->bus_ != nullptr) subscriber_->bus_->end(*subscriber_);
  subscriber_.reset();
}

SubscriptionDrops Subscription::drops() const {
  if (!subscriber_) return {};
  return {subscriber_->drop_count_, subscriber_->last_drop_reason_};
}

std::uint64_t Subscription::droppedCount() const { return subscriber_ ? subscriber_->drop_count_ : 0; }

bool Subscription::active() const { return subscriber_ && subscriber_->bus_ != nullptr; }

void Bus::handleAvailable() {
  while (handleFor(std::chrono::milliseconds(0))) {
  }
}

BusBackend::~BusBackend() {
  // A backend has ended its subscriptions already; whatever is left only loses its bus.
  for (auto& sub : subscribers_) sub->bus_ = nullptr;
}

Subscription BusBackend::subscribeWith(std::shared_ptr<Subscriber> sub, int queue_capacity) {
  sub->bus_ = this;
  attach(*sub, queue_capacity);
  subscribers_.push_back(sub);
  return Subscription(std::move(sub));
}

void BusBackend::end(Subscriber& sub) {
  if (sub.bus_ != this) return;
  detach(sub);
  sub.bus_ = nullptr;
  const auto it =
      std::find_if(subscribers_.begin(), subscribers_.end(), [&](const auto& s) { return s.get() == &sub; });
  if (it != subscribers_.end()) subscribers_.erase(it);
}

void BusBackend::endEverySubscription() {
  for (auto& sub : subscribers_) {
    detach(*sub);
    sub->bus_ = nullptr;
  }
  subscribers_.clear();
}

template <class Take>
void BusBackend::guardedCall(Subscriber& sub, Take&& take) {
  if (sub.bus_ == nullptr) return;
  // Keeps the subscriber alive through its handler, which may end its own subscription.
  const std::shared_ptr<Subscriber> keep = sub.shared_from_this();
  // Nothing may propagate through a backend's dispatch loop (LCM's is C): keep the first error.
  try {
    if (!take()) throw BadMessage(kUndecodable);
  } catch (const BadMessage& e) {
    ++dropped_;
    ++sub.drop_count_;
    sub.last_drop_reason_ = e.what();
  } catch (...) {
    if (!pending_) pending_ = std::current_exception();
  }
}

void BusBackend::deliver(Subscriber& sub, const void* data, std::size_t size) {
  guardedCall(sub, [&] { return sub.takeBytes(data, size); });
}

void BusBackend::deliver(Subscriber& sub, const MessageBox& box) {
  guardedCall(sub, [&] {
    if (sub.takeBox(box)) return true;
    // Another type on this channel: what a subscriber over LCM would get, the bytes (and a drop).
    box.encodeTo(convert_buffer_);
    return sub.takeBytes(convert_buffer_.data(), convert_buffer_.size());
  });
}

void BusBackend::rethrowPending() {
  if (pending_) {
    auto e = pending_;
    pending_ = nullptr;
    std::rethrow_exception(e);
  }
}

}  // namespace hunav
