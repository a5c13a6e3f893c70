#include "hunav/transport.hpp"

#include "hunav/channels.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <thread>

namespace hunav {

namespace {

constexpr std::string_view kChannelPortsOption = "channel_ports=1";
constexpr int kDefaultUdpmPort = 7667;

// Splits `url` into what comes before the query, and its options; true when it has our option
// (which is then left out of `options`).
bool splitChannelPortsOption(const std::string& url, std::string& head, std::vector<std::string>& options) {
  const std::size_t query = url.find('?');
  head = url.substr(0, query);
  options.clear();
  bool found = false;
  if (query == std::string::npos) return false;
  std::size_t begin = query + 1;
  while (begin <= url.size()) {
    const std::size_t end = std::min(url.find('&', begin), url.size());
    const std::string option = url.substr(begin, end - begin);
    if (option == kChannelPortsOption)
      found = true;
    else if (!option.empty())
      options.push_back(option);
    begin = end + 1;
  }
  return found;
}

bool isUdpm(const std::string& url) { return url.rfind("udpm://", 0) == 0; }

// `url` (udpm, with our option) for the port `offset` above its own, without our option.
std::string urlWithPortOffset(const std::string& url, int offset) {
  std::string head;
  std::vector<std::string> options;
  splitChannelPortsOption(url, head, options);
  // head: udpm://[ADDRESS[:PORT]]
  std::string address = head.substr(7);
  int port = kDefaultUdpmPort;
  if (const std::size_t colon = address.find(':'); colon != std::string::npos) {
    const std::string digits = address.substr(colon + 1);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos || digits.size() > 5)
      throw std::invalid_argument("bad port in LCM URL " + url);
    port = std::stoi(digits);
    address.resize(colon);
  }
  if (address.empty()) address = "239.255.76.67";  // LCM's default group
  port += offset;
  if (port > 65535) throw std::invalid_argument("LCM URL " + url + ": channel ports run past 65535");
  std::string out = "udpm://" + address + ":" + std::to_string(port);
  for (std::size_t i = 0; i < options.size(); ++i) out += (i == 0 ? "?" : "&") + options[i];
  return out;
}

}  // namespace

std::string lcmUrlForChannel(const std::string& url, std::string_view channel) {
  std::string head;
  std::vector<std::string> options;
  if (!isUdpm(url) || !splitChannelPortsOption(url, head, options)) return url;
  return urlWithPortOffset(url, channels::portOffset(channel));
}

std::string resolveLcmUrl(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  if (const char* env = std::getenv("LCM_DEFAULT_URL"); env != nullptr && *env != '\0') return env;
  return kDefaultLcmUrl;
}

Bus::Bus(lcm::LCM& lcm) : lcm_(&lcm) {
  if (!lcm_->good()) throw std::runtime_error("LCM is not usable (bad URL, or no multicast route?)");
}

Bus::Bus(const std::string& url) : url_(url) {
  std::string head;
  std::vector<std::string> options;
  channel_ports_ = isUdpm(url) && splitChannelPortsOption(url, head, options);
  lcm_ = &instanceFor(0);
}

lcm::LCM& Bus::instanceFor(int offset) {
  if (offset == 0 && lcm_ != nullptr) return *lcm_;
  for (auto& [o, instance] : owned_)
    if (o == offset) return *instance;
  const std::string url = channel_ports_ ? urlWithPortOffset(url_, offset) : url_;
  auto instance = std::make_unique<lcm::LCM>(url);
  if (!instance->good()) throw std::runtime_error("LCM is not usable on " + url + " (bad URL, or no multicast route?)");
  owned_.emplace_back(offset, std::move(instance));
  return *owned_.back().second;
}

Bus::Bus(InProcess) {}

Bus::~Bus() {
  for (auto& sub : subscriptions_)
    if (sub->lcm != nullptr) sub->lcm->unsubscribe(sub->handle);
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

void Bus::Subscription::deliver(const Box& box) {
  try {
    if (dispatchBox(box)) return;
    // Another type on this channel: what an LCM subscriber would get, the bytes (and a decode error).
    std::vector<std::uint8_t>& bytes = bus->convert_buffer_;
    box.encodeTo(bytes);
    dispatch(bytes.data(), static_cast<unsigned>(bytes.size()));
  } catch (const BadMessage&) {
    ++bus->dropped_;
  } catch (...) {
    if (!bus->pending_) bus->pending_ = std::current_exception();
  }
}

Bus::Channel& Bus::channelFor(std::string_view name) {
  // A handful of channels: a linear search beats hashing the name.
  for (auto& ch : channels_)
    if (ch->name == name) return *ch;
  auto ch = std::make_unique<Channel>();
  ch->name = std::string(name);
  if (lcm_ != nullptr) ch->lcm = channel_ports_ ? &instanceFor(channels::portOffset(name)) : lcm_;
  channels_.push_back(std::move(ch));
  return *channels_.back();
}

void Bus::attach(std::string_view channel, std::unique_ptr<Subscription> sub, int queue_capacity) {
  Channel& ch = channelFor(channel);
  if (lcm_ != nullptr) {
    sub->handle = ch.lcm->subscribe(ch.name, &Subscription::onRaw, sub.get());
    if (sub->handle == nullptr) throw std::runtime_error("cannot subscribe to " + ch.name);
    sub->handle->setQueueCapacity(queue_capacity);
    sub->lcm = ch.lcm;
    if (std::find(receivers_.begin(), receivers_.end(), ch.lcm) == receivers_.end()) {
      receivers_.push_back(ch.lcm);
      poll_fds_.push_back(pollfd{ch.lcm->getFileno(), POLLIN, 0});
    }
  } else {
    ch.subscribers.push_back(sub.get());
  }
  subscriptions_.push_back(std::move(sub));
}

bool Bus::dropForLossTest() {
  if (loss_probability_ <= 0.0) return false;
  // splitmix64: a tiny reproducible generator for the loss test hook.
  loss_state_ += 0x9E3779B97F4A7C15ULL;
  std::uint64_t z = loss_state_;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  if (static_cast<double>(z >> 11) * 0x1.0p-53 >= loss_probability_) return false;
  ++lost_for_testing_;
  return true;
}

void Bus::sendBytes(Channel& ch, const void* data, std::size_t size) {
  if (tap_) tap_(ch.name, data, size);
  if (ch.lcm != nullptr && ch.lcm->publish(ch.name, data, static_cast<unsigned>(size)) != 0)
    throw std::runtime_error("cannot publish on " + ch.name);
}

void Bus::publishRaw(std::string_view channel, const void* data, std::size_t size) {
  Channel& ch = channelFor(channel);
  if (dropForLossTest()) return;
  sendBytes(ch, data, size);
  if (lcm_ != nullptr || ch.subscribers.empty()) return;
  Queued q;
  q.channel = &ch;
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

void Bus::dispatchQueued(Queued& q) {
  Channel& ch = *q.channel;
  // By index: a handler may subscribe (and grow the list) while we dispatch.
  const std::size_t count = ch.subscribers.size();
  for (std::size_t i = 0; i < count; ++i) {
    if (q.box)
      ch.subscribers[i]->deliver(*q.box);
    else
      ch.subscribers[i]->deliver(q.data.data(), static_cast<unsigned>(q.data.size()));
  }
  if (q.box)
    ch.spare.push_back(std::move(q.box));
  else
    spare_buffers_.push_back(std::move(q.data));
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
    dispatchQueued(q);
    rethrowPending();
    return true;
  }
  lcm::LCM* ready = receivers_.empty() ? lcm_ : receivers_.front();
  int wait_ms = static_cast<int>(timeout.count());
  if (receivers_.size() > 1) {
    // Several ports: wait on all of them, then handle one message of a ready one (round robin, so
    // that a busy port cannot starve another).
    for (pollfd& p : poll_fds_) p.revents = 0;
    const int n = ::poll(poll_fds_.data(), poll_fds_.size(), wait_ms);
    if (n < 0) {
      if (errno == EINTR) return false;
      throw std::runtime_error("LCM handle failed (poll)");
    }
    if (n == 0) return false;
    for (std::size_t k = 0; k < receivers_.size(); ++k) {
      const std::size_t i = (next_receiver_ + k) % receivers_.size();
      if ((poll_fds_[i].revents & POLLIN) != 0) {
        ready = receivers_[i];
        next_receiver_ = i + 1;
        break;
      }
    }
    wait_ms = 0;
  }
  errno = 0;
  const int status = ready->handleTimeout(wait_ms);
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
