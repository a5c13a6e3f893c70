#include "hunav/transport.hpp"

#include <cerrno>
#include <cstdlib>
#include <thread>

namespace hunav {

std::string resolveLcmUrl(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env != nullptr && *env != '\0') return env;
  return kDefaultLcmUrl;
}

Bus::Bus(lcm::LCM& lcm) : lcm_(&lcm) {
  if (!lcm_->good()) throw std::runtime_error("LCM is not usable (bad URL, or no multicast route?)");
}

Bus::Bus(InProcess) {}

Bus::~Bus() {
  if (lcm_ != nullptr)
    for (auto& sub : subscriptions_) lcm_->unsubscribe(sub->handle);
}

void Bus::Subscription::onRaw(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  deliver(rbuf->data, rbuf->data_size);
}

void Bus::Subscription::deliver(const void* data, unsigned size) {
  // Nothing may propagate through LCM's C dispatch loop: keep the first error for the caller.
  try {
    dispatch(data, size);
  } catch (const BadMessage&) {
    ++bus->dropped_;
  } catch (...) {
    if (!bus->pending_) bus->pending_ = std::current_exception();
  }
}

void Bus::attach(const std::string& channel, std::unique_ptr<Subscription> sub, int queue_capacity) {
  sub->channel = channel;
  if (lcm_ != nullptr) {
    sub->handle = lcm_->subscribe(channel, &Subscription::onRaw, sub.get());
    if (sub->handle == nullptr) throw std::runtime_error("cannot subscribe to " + channel);
    sub->handle->setQueueCapacity(queue_capacity);
  }
  subscriptions_.push_back(std::move(sub));
}

void Bus::publishRaw(const std::string& channel, const void* data, std::size_t size) {
  if (loss_probability_ > 0.0) {
    // splitmix64: a tiny reproducible generator for the loss test hook.
    loss_state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = loss_state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    if (static_cast<double>(z >> 11) * 0x1.0p-53 < loss_probability_) {
      ++lost_for_testing_;
      return;
    }
  }
  if (tap_) tap_(channel, data, size);
  if (lcm_ != nullptr) {
    if (lcm_->publish(channel, data, static_cast<unsigned>(size)) != 0)
      throw std::runtime_error("cannot publish on " + channel);
    return;
  }
  Queued q;
  q.channel = channel;
  if (!spare_buffers_.empty()) {
    q.data = std::move(spare_buffers_.back());
    spare_buffers_.pop_back();
  }
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  q.data.assign(bytes, bytes + size);
  queue_.push_back(std::move(q));
}

void Bus::setOutgoingLossForTesting(double probability, std::uint64_t seed) {
  loss_probability_ = probability;
  loss_state_ = seed;
}

bool Bus::handleFor(std::chrono::milliseconds timeout) {
  if (lcm_ == nullptr) {
    if (queue_.empty()) {
      // Single-threaded: nothing can arrive while we wait, but a caller's timeout must still elapse.
      if (timeout.count() > 0) std::this_thread::sleep_for(timeout);
      return false;
    }
    Queued q = std::move(queue_.front());
    queue_.pop_front();
    // By index: a handler may subscribe (and grow the list) while we dispatch.
    const std::size_t count = subscriptions_.size();
    for (std::size_t i = 0; i < count; ++i)
      if (subscriptions_[i]->channel == q.channel)
        subscriptions_[i]->deliver(q.data.data(), static_cast<unsigned>(q.data.size()));
    spare_buffers_.push_back(std::move(q.data));
    rethrowPending();
    return true;
  }
  errno = 0;
  const int status = lcm_->handleTimeout(static_cast<int>(timeout.count()));
  if (status < 0) {
    if (errno == EINTR) return false;  // a signal (SIGINT/SIGTERM) woke us: let the caller check its flag
    throw std::runtime_error("LCM handle failed");
  }
  rethrowPending();
  return status > 0;
}

void Bus::handleAvailable() {
  while (handleFor(std::chrono::milliseconds(0))) {
  }
}

void Bus::rethrowPending() {
  if (pending_) {
    auto e = pending_;
    pending_ = nullptr;
    std::rethrow_exception(e);
  }
}

}  // namespace hunav
