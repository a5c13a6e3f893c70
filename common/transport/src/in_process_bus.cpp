#include "hunav/in_process_bus.hpp"

#include <thread>

#include "local_queue.hpp"

namespace hunav {

struct InProcessBus::Queue : detail::LocalQueue {};

InProcessBus::InProcessBus() : queue_(std::make_unique<Queue>()) {}

InProcessBus::~InProcessBus() { endEverySubscription(); }

void InProcessBus::attach(Subscriber& sub, int /*queue_capacity: the queue holds what is in flight*/) {
  queue_->add(queue_->channel(sub.channel()), sub);
}

void InProcessBus::detach(Subscriber& sub) { queue_->remove(sub); }

void InProcessBus::publishMessage(std::string_view channel, const OutgoingMessage& msg) {
  detail::LocalChannel& ch = queue_->channel(channel);
  // As over LCM: a message nobody subscribes to is not queued.
  if (detail::LocalQueue::hasSubscribers(ch)) queue_->pushMessage(ch, msg);
}

void InProcessBus::publishRaw(std::string_view channel, const void* data, std::size_t size) {
  detail::LocalChannel& ch = queue_->channel(channel);
  if (detail::LocalQueue::hasSubscribers(ch)) queue_->pushBytes(ch, data, size);
}

bool InProcessBus::handleFor(std::chrono::milliseconds timeout) {
  if (queue_->empty()) {
    // Nothing can arrive while we wait, but a caller's timeout must still elapse.
    if (timeout.count() > 0) std::this_thread::sleep_for(timeout);
    return false;
  }
  queue_->dispatchFront([this](Subscriber& sub, const detail::QueuedMessage& q) {
    if (q.box)
      deliver(sub, *q.box);
    else
      deliver(sub, q.data.data(), q.data.size());
  });
  rethrowPending();
  return true;
}

}  // namespace hunav
