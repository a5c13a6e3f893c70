#include "hunav/lcm_bus.hpp"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

#include "hunav/channels.hpp"
#include "lcm_url.hpp"

namespace hunav {

struct LcmBus::Instances {
  // One LCM subscription: where LCM's C dispatch loop calls back into this bus.
  struct Entry {
    LcmBus* bus = nullptr;
    Subscriber* sub = nullptr;
    lcm::LCM* lcm = nullptr;
    lcm::Subscription* handle = nullptr;
    void onRaw(const lcm::ReceiveBuffer* rbuf, const std::string&) {
      if (sub != nullptr) bus->deliverFromLcm(*sub, *rbuf);
    }
  };

  // handleTimeout on one instance; subscriptions ended by a handler meanwhile leave LCM after it.
  int handleOne(lcm::LCM& lcm, int timeout_ms) {
    dispatching = true;
    errno = 0;
    const int status = lcm.handleTimeout(timeout_ms);
    const int saved_errno = errno;
    dispatching = false;
    for (auto it = entries.begin(); it != entries.end();) {
      if ((*it)->sub == nullptr) {
        (*it)->lcm->unsubscribe((*it)->handle);
        it = entries.erase(it);
      } else {
        ++it;
      }
    }
    errno = saved_errno;
    return status;
  }

  lcm::LCM& forChannel(std::string_view channel) {
    const int offset = channel_ports ? channels::portOffset(channel) : 0;
    return offset == 0 && main != nullptr ? *main : owned.at(offset);
  }
  void addReceiver(lcm::LCM& lcm) {
    if (std::find(receivers.begin(), receivers.end(), &lcm) != receivers.end()) return;
    receivers.push_back(&lcm);
    poll_fds.push_back(pollfd{lcm.getFileno(), POLLIN, 0});
  }

  bool channel_ports = false;
  lcm::LCM* main = nullptr;        // the caller's instance (LcmBus(lcm::LCM&)), or null
  detail::LcmInstances owned{""};  // else ours, one per port
  std::vector<std::unique_ptr<Entry>> entries;
  std::vector<lcm::LCM*> receivers;  // instances with subscriptions: what handleFor() waits on
  std::vector<pollfd> poll_fds;
  std::size_t next_receiver = 0;  // round robin among ready instances
  bool dispatching = false;
  detail::ChannelNames channel_names;  // inside LCM's handleTimeout
};

LcmBus::LcmBus(const std::string& url) : lcm_(std::make_unique<Instances>()) {
  lcm_->owned = detail::LcmInstances(url);
  lcm_->channel_ports = detail::hasChannelPorts(url);
  lcm_->forChannel("");  // opens the URL's own port now, so that a bad URL fails here
}

LcmBus::LcmBus(lcm::LCM& lcm) : lcm_(std::make_unique<Instances>()) {
  if (!lcm.good()) throw std::runtime_error("LCM is not usable (bad URL, or no multicast route?)");
  lcm_->main = &lcm;
}

LcmBus::~LcmBus() { endEverySubscription(); }

void LcmBus::deliverFromLcm(Subscriber& sub, const lcm::ReceiveBuffer& rbuf) {
  deliver(sub, rbuf.data, rbuf.data_size);
}

void LcmBus::attach(Subscriber& sub, int queue_capacity) {
  lcm::LCM& lcm = lcm_->forChannel(sub.channel());
  auto entry = std::make_unique<Instances::Entry>();
  entry->bus = this;
  entry->sub = &sub;
  entry->lcm = &lcm;
  entry->handle = lcm.subscribe(sub.channel(), &Instances::Entry::onRaw, entry.get());
  if (entry->handle == nullptr) throw std::runtime_error("cannot subscribe to " + sub.channel());
  entry->handle->setQueueCapacity(queue_capacity);
  lcm_->addReceiver(lcm);
  lcm_->entries.push_back(std::move(entry));
}

void LcmBus::detach(Subscriber& sub) {
  auto& entries = lcm_->entries;
  for (auto it = entries.begin(); it != entries.end(); ++it) {
    if ((*it)->sub != &sub) continue;
    if (lcm_->dispatching) {
      (*it)->sub = nullptr;  // unsubscribed from LCM once its dispatch returns (handleOne)
      return;
    }
    (*it)->lcm->unsubscribe((*it)->handle);
    entries.erase(it);
    return;
  }
}

void LcmBus::publishMessage(std::string_view channel, const OutgoingMessage& msg) {
  const auto [data, size] = detail::bytesOf(msg, buffer_);
  publishRaw(channel, data, size);
}

void LcmBus::publishRaw(std::string_view channel, const void* data, std::size_t size) {
  const std::string& name = lcm_->channel_names.of(channel);
  if (lcm_->forChannel(name).publish(name, data, static_cast<unsigned>(size)) != 0)
    throw std::runtime_error("cannot publish on " + name);
}

bool LcmBus::handleFor(std::chrono::milliseconds timeout) {
  auto& receivers = lcm_->receivers;
  if (receivers.size() <= 1) {
    // Nothing subscribed, or one instance: LCM waits itself (one system call less than a poll first).
    lcm::LCM& only = receivers.empty() ? lcm_->forChannel("") : *receivers.front();
    const int status = lcm_->handleOne(only, static_cast<int>(timeout.count()));
    if (status < 0) {
      if (errno == EINTR) return false;  // a signal (SIGINT/SIGTERM) woke us: let the caller check its flag
      throw std::runtime_error("LCM handle failed");
    }
    rethrowPending();
    return status > 0;
  }
  // Wait on every port at once, then handle a message of a ready one (round robin, so that a busy
  // port cannot starve another).
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    const int wait_ms = static_cast<int>(std::max<std::chrono::milliseconds::rep>(left.count(), 0));
    for (pollfd& p : lcm_->poll_fds) p.revents = 0;
    const int n = ::poll(lcm_->poll_fds.data(), lcm_->poll_fds.size(), wait_ms);
    if (n < 0) {
      if (errno == EINTR) return false;
      throw std::runtime_error("LCM handle failed (poll)");
    }
    if (n == 0) return false;
    std::size_t ready = receivers.size();
    for (std::size_t k = 0; k < receivers.size(); ++k) {
      const std::size_t i = (lcm_->next_receiver + k) % receivers.size();
      if ((lcm_->poll_fds[i].revents & (POLLIN | POLLERR)) != 0) {
        ready = i;
        lcm_->next_receiver = i + 1;
        break;
      }
    }
    if (ready == receivers.size()) return false;  // only POLLHUP/POLLNVAL: nothing to read
    const int status = lcm_->handleOne(*receivers[ready], 0);
    if (status < 0) {
      if (errno == EINTR) return false;
      throw std::runtime_error("LCM handle failed");
    }
    rethrowPending();
    if (status > 0) return true;
    if (wait_ms == 0) return false;
  }
}

}  // namespace hunav
