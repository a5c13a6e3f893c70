#include "hunav/transport.hpp"

#include <cerrno>
#include <cstdlib>

namespace hunav {

std::string resolveLcmUrl(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env != nullptr && *env != '\0') return env;
  return kDefaultLcmUrl;
}

Bus::Bus(lcm::LCM& lcm) : lcm_(lcm) {
  if (!lcm_.good()) throw std::runtime_error("LCM is not usable (bad URL, or no multicast route?)");
}

Bus::~Bus() {
  for (auto& sub : subscriptions_) lcm_.unsubscribe(sub->handle);
}

void Bus::Subscription::onRaw(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  // Nothing may propagate through LCM's C dispatch loop: keep the first error for the caller.
  try {
    dispatch(rbuf->data, rbuf->data_size);
  } catch (const BadMessage&) {
    ++bus->dropped_;
  } catch (...) {
    if (!bus->pending_) bus->pending_ = std::current_exception();
  }
}

void Bus::attach(const std::string& channel, std::unique_ptr<Subscription> sub, int queue_capacity) {
  sub->handle = lcm_.subscribe(channel, &Subscription::onRaw, sub.get());
  if (sub->handle == nullptr) throw std::runtime_error("cannot subscribe to " + channel);
  sub->handle->setQueueCapacity(queue_capacity);
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
  if (lcm_.publish(channel, data, static_cast<unsigned>(size)) != 0)
    throw std::runtime_error("cannot publish on " + channel);
}

void Bus::setOutgoingLossForTesting(double probability, std::uint64_t seed) {
  loss_probability_ = probability;
  loss_state_ = seed;
}

bool Bus::handleFor(std::chrono::milliseconds timeout) {
  errno = 0;
  const int status = lcm_.handleTimeout(static_cast<int>(timeout.count()));
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
