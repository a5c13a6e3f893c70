#include "hunav/udpm_bus.hpp"

#include <poll.h>

#include <algorithm>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <thread>

#include "direct_receiver.hpp"
#include "hunav/channels.hpp"
#include "lcm_url.hpp"
#include "local_queue.hpp"

namespace hunav {

using Clock = std::chrono::steady_clock;

struct UdpmBus::Ports {
  // The LCM instance that publishes on `offset`'s port, opened on first use (it never opens a receive
  // socket: nothing subscribes through it).
  lcm::LCM& sender(int offset) { return senders.at(offset); }
  // Our receive socket of `offset`'s port, opened on first use.
  detail::DirectReceiver& receiver(int offset) {
    for (auto& [o, r] : receivers)
      if (o == offset) return *r;
    receivers.emplace_back(offset, std::make_unique<detail::DirectReceiver>(detail::lcmUrlAtOffset(url, offset)));
    poll_fds.push_back(pollfd{receivers.back().second->fd(), POLLIN, 0});
    return *receivers.back().second;
  }
  int offsetOf(std::string_view channel) const { return channel_ports ? channels::portOffset(channel) : 0; }
  // Lets the kernel pass only the channels subscribed to on `offset`'s port.
  void updateFilter(int offset) {
    std::vector<std::string> names;
    for (const auto& ch : queue.channels())
      if (ch->port_offset == offset && detail::LocalQueue::hasSubscribers(*ch)) names.push_back(ch->name);
    receiver(offset).setChannelFilter(names, sample_every);
  }
  // Reads what `r` has and queues the messages of channels subscribed to.
  void drain(detail::DirectReceiver& r) {
    r.drain([this](const detail::DirectReceiver::Message& m) {
      for (const auto& ch : queue.channels()) {
        if (ch->name != m.channel) continue;
        if (detail::LocalQueue::hasSubscribers(*ch)) queue.pushBytes(*ch, m.data, m.size);
        return;
      }
    });
  }
  void drainAll() {
    for (auto& entry : receivers) drain(*entry.second);
    last_drain = Clock::now();
    dispatched_since_drain = 0;
  }

  std::string url;
  bool channel_ports = false;
  ReceiveOptions options;
  std::map<std::string, std::uint32_t> sample_every;                               // sampleChannel()
  detail::LcmInstances senders{""};                                                // one per port
  std::vector<std::pair<int, std::unique_ptr<detail::DirectReceiver>>> receivers;  // port offset, socket
  std::vector<pollfd> poll_fds;                                                    // of receivers, in the same order
  std::size_t next_receiver = 0;                                                   // round robin among ready sockets
  detail::LocalQueue queue;                                                        // messages read, not yet dispatched
  Clock::time_point last_drain{};
  int dispatched_since_drain = 0;
  std::vector<std::uint8_t> buffer;
  detail::ChannelNames channel_names;
};

UdpmBus::UdpmBus(const std::string& url, const ReceiveOptions& options) : ports_(std::make_unique<Ports>()) {
  if (!detail::isUdpm(url)) throw std::invalid_argument("not a udpm:// URL: " + url);
  ports_->url = url;
  ports_->senders = detail::LcmInstances(url);
  ports_->channel_ports = detail::hasChannelPorts(url);
  ports_->options = options;
  ports_->sender(0);  // a bad URL or a missing route fails here
}

UdpmBus::~UdpmBus() { endEverySubscription(); }

void UdpmBus::attach(Subscriber& sub, int /*queue_capacity: our queue never drops*/) {
  detail::LocalChannel& ch = ports_->queue.channel(sub.channel());
  ch.port_offset = ports_->offsetOf(sub.channel());
  ports_->receiver(ch.port_offset);
  ports_->queue.add(ch, sub);
  if (ports_->options.filter_unsubscribed_channels) ports_->updateFilter(ch.port_offset);
}

void UdpmBus::detach(Subscriber& sub) {
  ports_->queue.remove(sub);
  if (ports_->options.filter_unsubscribed_channels) ports_->updateFilter(ports_->offsetOf(sub.channel()));
}

bool UdpmBus::sampleChannel(std::string_view channel, std::uint32_t every) {
  if (!ports_->options.filter_unsubscribed_channels) return false;  // no filter to sample in
  const std::string name(channel);
  if (every <= 1)
    ports_->sample_every.erase(name);
  else
    ports_->sample_every[name] = every;
  const int offset = ports_->offsetOf(name);
  for (const auto& entry : ports_->receivers)
    if (entry.first == offset) ports_->updateFilter(offset);  // a port already listened to
  return true;
}

void UdpmBus::publishMessage(std::string_view channel, const OutgoingMessage& msg) {
  const auto [data, size] = detail::bytesOf(msg, ports_->buffer);
  publishRaw(channel, data, size);
}

void UdpmBus::publishRaw(std::string_view channel, const void* data, std::size_t size) {
  const std::string& name = ports_->channel_names.of(channel);
  if (ports_->sender(ports_->offsetOf(name)).publish(name, data, static_cast<unsigned>(size)) != 0)
    throw std::runtime_error("cannot publish on " + name);
}

ReceiveLosses UdpmBus::receiveLosses() const {
  ReceiveLosses losses;
  for (const auto& entry : ports_->receivers) {
    const detail::DirectReceiver& r = *entry.second;
    if (!r.filtered()) losses.overflowed_datagrams += r.kernelDrops();
    losses.incomplete_messages += r.incompleteMessages();
  }
  return losses;
}

std::uint64_t UdpmBus::malformedDatagrams() const {
  std::uint64_t total = 0;
  for (const auto& entry : ports_->receivers) total += entry.second->malformed();
  return total;
}

std::uint64_t UdpmBus::droppedMessages() const { return BusBackend::droppedMessages() + malformedDatagrams(); }

std::uint64_t UdpmBus::datagramsRead() const {
  std::uint64_t total = 0;
  for (const auto& entry : ports_->receivers) total += entry.second->datagramsRead();
  return total;
}

bool UdpmBus::handleFor(std::chrono::milliseconds timeout) {
  Ports& p = *ports_;
  const auto deliverQueued = [this](Subscriber& sub, const detail::QueuedMessage& q) {
    deliver(sub, q.data.data(), q.data.size());
  };
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    if (!p.queue.empty()) {
      // A backlog: read the sockets again every few messages or every millisecond, so that what
      // arrives meanwhile waits in our queue rather than filling a socket buffer.
      if (++p.dispatched_since_drain >= kBacklogDrainMessages || Clock::now() - p.last_drain >= kBacklogDrainPeriod)
        p.drainAll();
      p.queue.dispatchFront(deliverQueued);
      rethrowPending();
      return true;
    }
    if (p.receivers.empty()) {
      // Nothing subscribed: nothing can arrive, but a caller's timeout must still elapse.
      if (timeout.count() > 0) std::this_thread::sleep_until(deadline);
      return false;
    }
    if (p.options.min_wake_interval.count() > 0) {
      // Let what arrives meanwhile pile up in the sockets, to be read in one batch.
      const auto wake_at = std::min(p.last_drain + p.options.min_wake_interval, deadline);
      if (Clock::now() < wake_at) std::this_thread::sleep_until(wake_at);
    }
    // Wait on every port at once, then read a ready one (round robin, so that a busy port cannot
    // starve another).
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
    const int wait_ms = static_cast<int>(std::max<std::chrono::milliseconds::rep>(left.count(), 0));
    for (pollfd& fd : p.poll_fds) fd.revents = 0;
    const int n = ::poll(p.poll_fds.data(), p.poll_fds.size(), wait_ms);
    if (n < 0) {
      if (errno == EINTR) return false;  // a signal (SIGINT/SIGTERM) woke us: let the caller check its flag
      throw std::runtime_error("receive failed (poll)");
    }
    if (n == 0) return false;
    std::size_t ready = p.receivers.size();
    for (std::size_t k = 0; k < p.receivers.size(); ++k) {
      const std::size_t i = (p.next_receiver + k) % p.receivers.size();
      if ((p.poll_fds[i].revents & (POLLIN | POLLERR)) != 0) {
        ready = i;
        p.next_receiver = i + 1;
        break;
      }
    }
    if (ready == p.receivers.size()) return false;  // only POLLHUP/POLLNVAL: nothing to read
    p.drain(*p.receivers[ready].second);
    p.last_drain = Clock::now();
    p.dispatched_since_drain = 0;
    if (p.queue.empty() && wait_ms == 0) return false;
    // Otherwise a message to dispatch, or a datagram nobody here listens to or a fragment: wait on.
  }
}

}  // namespace hunav
