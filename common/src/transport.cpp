#include "hunav/transport.hpp"

#include <arpa/inet.h>
#include <linux/filter.h>
#include <linux/sock_diag.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "hunav/channels.hpp"

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

// The parts of a udpm URL our receive socket needs.
struct UdpmEndpoint {
  in_addr group{};
  int port = kDefaultUdpmPort;
  int recv_buf_size = 0;  // 0: the system's default
};

UdpmEndpoint parseUdpm(const std::string& url) {
  UdpmEndpoint e;
  const std::size_t query = url.find('?');
  std::string address = url.substr(7, query == std::string::npos ? std::string::npos : query - 7);
  if (const std::size_t colon = address.find(':'); colon != std::string::npos) {
    e.port = std::stoi(address.substr(colon + 1));
    address.resize(colon);
  }
  if (address.empty()) address = "239.255.76.67";
  if (::inet_aton(address.c_str(), &e.group) == 0) throw std::invalid_argument("bad address in LCM URL " + url);
  if (query != std::string::npos) {
    std::size_t begin = query + 1;
    while (begin < url.size()) {
      const std::size_t end = std::min(url.find('&', begin), url.size());
      const std::string option = url.substr(begin, end - begin);
      if (option.rfind("recv_buf_size=", 0) == 0) e.recv_buf_size = std::stoi(option.substr(14));
      begin = end + 1;
    }
  }
  return e;
}

std::uint32_t bigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
std::uint16_t bigEndian16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }

}  // namespace

// A receive socket on one udpm port, read in the caller's thread, in LCM's wire format (LCM 1.3.1,
// lcm_udpm.c): a datagram is either a whole message, "LC02" | seqno | channel NUL | payload, or one
// fragment of a long one, "LC03" | seqno | size | offset | fragment no | fragment count, then for
// fragment 0 the channel NUL, then the fragment's bytes (all integers big-endian). The socket is set
// up as LCM sets up its own (address reuse, so several processes share the port; the group joined
// on the interface the multicast route names, loopback in our namespaces).
// Losses are counted, never silent: datagrams the kernel dropped for a full receive buffer (the
// socket's drop count), and long messages that lost a fragment.
class DirectReceiver {
 public:
  struct Message {
    std::string_view channel;
    const std::uint8_t* data;
    std::size_t size;
  };

  explicit DirectReceiver(const std::string& url) {
    const UdpmEndpoint e = parseUdpm(url);
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw std::runtime_error("cannot open a UDP socket for " + url);
    const int one = 1;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_ANY);
    addr.sin_port = htons(static_cast<std::uint16_t>(e.port));
    ip_mreq membership{};
    membership.imr_multiaddr = e.group;
    membership.imr_interface.s_addr = htonl(INADDR_ANY);
    // The buffer the URL asks for; SO_RCVBUFFORCE (root) goes past net.core.rmem_max, which would
    // otherwise cap it silently.
    const bool buffer_set =
        e.recv_buf_size <= 0 ||
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &e.recv_buf_size, sizeof e.recv_buf_size) == 0 ||
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &e.recv_buf_size, sizeof e.recv_buf_size) == 0;
    if (::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0 ||
        ::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 || !buffer_set ||
        ::setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &membership, sizeof membership) != 0) {
      const std::string why = std::strerror(errno);
      ::close(fd_);
      throw std::runtime_error("cannot receive on " + url + ": " + why + " (no multicast route?)");
    }
    for (std::size_t i = 0; i < kBatch; ++i) {
      iov_[i] = iovec{datagrams_[i].data(), datagrams_[i].size()};
      headers_[i].msg_hdr.msg_iov = &iov_[i];
      headers_[i].msg_hdr.msg_iovlen = 1;
      headers_[i].msg_hdr.msg_name = &senders_[i];
    }
  }
  ~DirectReceiver() { ::close(fd_); }
  DirectReceiver(const DirectReceiver&) = delete;
  DirectReceiver& operator=(const DirectReceiver&) = delete;

  int fd() const { return fd_; }
  std::uint64_t malformed() const { return malformed_; }
  std::uint64_t incompleteMessages() const { return incomplete_; }
  std::uint64_t datagramsRead() const { return datagrams_read_; }
  bool filtered() const { return filtered_; }

  // Datagrams the kernel dropped on this socket: a full receive buffer, or (with a filter) the
  // filter's work.
  std::uint64_t kernelDrops() const {
    std::uint32_t info[SK_MEMINFO_VARS] = {};
    socklen_t size = sizeof info;
    if (::getsockopt(fd_, SOL_SOCKET, SO_MEMINFO, info, &size) != 0 || size <= SK_MEMINFO_DROPS * sizeof info[0])
      return 0;
    return info[SK_MEMINFO_DROPS];
  }

  // Lets the kernel pass only short messages (LC02) on these channels, fragments (LC03: only the
  // first names its channel) and anything else (counted as malformed here); drops the rest. A
  // classic BPF program: for a UDP socket it sees the datagram from the UDP header (8 bytes) on.
  void setChannelFilter(const std::vector<std::string>& channels) {
    constexpr std::uint32_t kPayload = 8;  // the UDP header
    constexpr std::uint32_t kAccept = 0xFFFFFFFFu, kDrop = 0;
    std::vector<sock_filter> program;
    program.push_back(BPF_STMT(BPF_LD | BPF_W | BPF_ABS, kPayload));
    program.push_back(BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, kMagicShort, 1, 0));
    program.push_back(BPF_STMT(BPF_RET | BPF_K, kAccept));
    for (const std::string& name : channels) {
      // The name and its NUL, compared a big-endian word at a time; the last word masked.
      std::vector<std::uint8_t> bytes(name.begin(), name.end());
      bytes.push_back(0);
      const std::size_t words = (bytes.size() + 3) / 4;
      bytes.resize(words * 4, 0);
      const std::size_t tail = (name.size() + 1) % 4;  // bytes of the last word that count (0: all)
      // Instructions of the block: per word a load, a compare and, for a partial last word, a mask;
      // then the accept. A mismatch jumps past the rest of the block.
      const std::size_t block = words * 2 + (tail != 0 ? 1 : 0) + 1;
      if (block > 255 || program.size() + block + 1 > BPF_MAXINSNS) return;  // cannot express it: no filter
      for (std::size_t w = 0; w < words; ++w) {
        program.push_back(BPF_STMT(BPF_LD | BPF_W | BPF_ABS, static_cast<std::uint32_t>(kPayload + 8 + 4 * w)));
        std::uint32_t value = bigEndian32(&bytes[4 * w]);
        if (w + 1 == words && tail != 0) {
          const std::uint32_t mask = ~std::uint32_t{0} << (8 * (4 - tail));
          program.push_back(BPF_STMT(BPF_ALU | BPF_AND | BPF_K, mask));
          value &= mask;
        }
        const std::size_t done = program.size() + 1;  // after this compare
        const std::size_t block_end =
            done + (words - 1 - w) * 2 + 1 + ((tail != 0 && w + 1 < words) ? 1 : 0);  // the accept included
        program.push_back(BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, value, 0, static_cast<std::uint8_t>(block_end - done)));
      }
      program.push_back(BPF_STMT(BPF_RET | BPF_K, kAccept));
    }
    program.push_back(BPF_STMT(BPF_RET | BPF_K, kDrop));
    sock_fprog fprog{static_cast<unsigned short>(program.size()), program.data()};
    if (::setsockopt(fd_, SOL_SOCKET, SO_ATTACH_FILTER, &fprog, sizeof fprog) != 0)
      throw std::runtime_error(std::string("cannot filter a receive socket: ") + std::strerror(errno));
    filtered_ = true;
  }

  // Reads every datagram waiting (without blocking) and calls `take` with each complete message.
  template <class Take>
  void drain(Take&& take) {
    for (;;) {
      for (std::size_t i = 0; i < kBatch; ++i) headers_[i].msg_hdr.msg_namelen = sizeof(sockaddr_in);
      const int n = ::recvmmsg(fd_, headers_.data(), kBatch, MSG_DONTWAIT, nullptr);
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return;
        throw std::runtime_error(std::string("receive failed: ") + std::strerror(errno));
      }
      datagrams_read_ += static_cast<std::uint64_t>(n);
      for (int i = 0; i < n; ++i)
        parse(datagrams_[static_cast<std::size_t>(i)].data(), headers_[static_cast<std::size_t>(i)].msg_len,
              senders_[static_cast<std::size_t>(i)], take);
      if (n < static_cast<int>(kBatch)) return;
    }
  }

 private:
  static constexpr std::uint32_t kMagicShort = 0x4c433032;  // "LC02"
  static constexpr std::uint32_t kMagicLong = 0x4c433033;   // "LC03"
  static constexpr std::size_t kLongHeader = 20;
  static constexpr std::size_t kBatch = 8;
  static constexpr std::size_t kMaxDatagram = 65536;
  static constexpr std::uint32_t kMaxMessage = 256u << 20;  // as LCM: larger ones are refused

  // A long message being put together, one per sender (LCM's publishers send fragments in order,
  // one message at a time; a new sequence number from a sender drops its unfinished one).
  struct Assembly {
    sockaddr_in from{};
    std::uint32_t seqno = 0;
    std::uint16_t remaining = 0;
    bool skipping = false;  // the fragments of skip_seqno are of a message already given up
    std::uint32_t skip_seqno = 0;
    std::string channel;
    std::vector<std::uint8_t> data;
  };

  // The channel name that starts `p` (NUL-terminated within `end`), or false.
  static bool channelAt(const std::uint8_t* p, const std::uint8_t* end, std::string_view& channel) {
    const void* nul = std::memchr(p, 0, static_cast<std::size_t>(end - p));
    if (nul == nullptr) return false;
    channel = std::string_view(reinterpret_cast<const char*>(p), static_cast<const std::uint8_t*>(nul) - p);
    return !channel.empty();
  }

  template <class Take>
  void parse(const std::uint8_t* p, std::size_t size, const sockaddr_in& from, Take& take) {
    const std::uint8_t* end = p + size;
    if (size < 8) {
      ++malformed_;
      return;
    }
    const std::uint32_t magic = bigEndian32(p);
    if (magic == kMagicShort) {
      std::string_view channel;
      if (!channelAt(p + 8, end, channel)) {
        ++malformed_;
        return;
      }
      const std::uint8_t* payload = p + 8 + channel.size() + 1;
      take(Message{channel, payload, static_cast<std::size_t>(end - payload)});
      return;
    }
    if (magic != kMagicLong || size < kLongHeader) {
      ++malformed_;
      return;
    }
    const std::uint32_t seqno = bigEndian32(p + 4);
    const std::uint32_t total = bigEndian32(p + 8);
    const std::uint32_t offset = bigEndian32(p + 12);
    const std::uint16_t fragment = bigEndian16(p + 16);
    const std::uint16_t fragments = bigEndian16(p + 18);
    const std::uint8_t* body = p + kLongHeader;
    Assembly* a = nullptr;
    for (Assembly& candidate : assemblies_)
      if (candidate.from.sin_addr.s_addr == from.sin_addr.s_addr && candidate.from.sin_port == from.sin_port)
        a = &candidate;
    if (a == nullptr) {
      assemblies_.emplace_back();
      a = &assemblies_.back();
      a->from = from;
      a->remaining = 0;
    }
    if (fragment == 0) {
      // The first fragment (re)starts a message; one still unfinished lost its last fragments.
      if (a->remaining != 0) ++incomplete_;
      std::string_view channel;
      if (total > kMaxMessage || fragments == 0 || !channelAt(body, end, channel)) {
        ++malformed_;
        giveUp(*a, seqno);
        return;
      }
      a->seqno = seqno;
      a->skipping = false;
      a->channel.assign(channel);
      a->data.resize(total);
      a->remaining = fragments;
      body += channel.size() + 1;
    } else if (a->remaining == 0 || a->seqno != seqno) {
      // A fragment of a message whose start we missed (counted once), and of one being put
      // together, the end lost.
      if (a->remaining != 0) ++incomplete_;
      if (!a->skipping || a->skip_seqno != seqno) ++incomplete_;
      giveUp(*a, seqno);
      return;
    }
    const std::size_t length = static_cast<std::size_t>(end - body);
    if (offset > a->data.size() || length > a->data.size() - offset) {
      ++malformed_;
      giveUp(*a, seqno);
      return;
    }
    std::memcpy(a->data.data() + offset, body, length);
    if (--a->remaining == 0) take(Message{a->channel, a->data.data(), a->data.size()});
  }

  // Drops the message being put together and the rest of message `seqno`.
  static void giveUp(Assembly& a, std::uint32_t seqno) {
    a.remaining = 0;
    a.skipping = true;
    a.skip_seqno = seqno;
  }

  int fd_ = -1;
  bool filtered_ = false;
  std::uint64_t incomplete_ = 0;
  std::uint64_t datagrams_read_ = 0;
  std::array<std::array<std::uint8_t, kMaxDatagram>, kBatch> datagrams_{};
  std::array<iovec, kBatch> iov_{};
  std::array<mmsghdr, kBatch> headers_{};
  std::array<sockaddr_in, kBatch> senders_{};
  std::deque<Assembly> assemblies_;
  std::uint64_t malformed_ = 0;
};

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

Bus::Bus(const std::string& url, bool direct_on_every_port) : Bus(url, BusOptions{direct_on_every_port, false}) {}

Bus::Bus(const std::string& url, const BusOptions& options) : url_(url), options_(options) {
  std::string head;
  std::vector<std::string> url_options;
  channel_ports_ = isUdpm(url) && splitChannelPortsOption(url, head, url_options);
  options_.direct_on_every_port = options.direct_on_every_port && isUdpm(url);
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
  } catch (const BadMessage& e) {
    drop(e.what());
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
  } catch (const BadMessage& e) {
    drop(e.what());
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
  const int offset = channel_ports_ ? channels::portOffset(ch.name) : 0;
  if (lcm_ != nullptr && offset == 0 && !options_.direct_on_every_port) {
    sub->handle = ch.lcm->subscribe(ch.name, &Subscription::onRaw, sub.get());
    if (sub->handle == nullptr) throw std::runtime_error("cannot subscribe to " + ch.name);
    sub->handle->setQueueCapacity(queue_capacity);
    sub->lcm = ch.lcm;
    addReceiver(ch.lcm, nullptr, ch.lcm->getFileno());
  } else {
    // In process, or a channel of its own port read by our direct receiver. Both queue without a
    // bound: the step protocol has at most a resend or two in flight.
    if (lcm_ != nullptr && ch.direct == nullptr) {
      ch.direct = &directReceiverFor(offset);
      addReceiver(nullptr, ch.direct, ch.direct->fd());
    }
    ch.subscribers.push_back(sub.get());
    if (ch.direct != nullptr && options_.filter_unsubscribed_channels) updateFilter(*ch.direct);
  }
  subscriptions_.push_back(std::move(sub));
}

void Bus::updateFilter(DirectReceiver& receiver) {
  std::vector<std::string> names;
  for (const auto& ch : channels_)
    if (ch->direct == &receiver && !ch->subscribers.empty()) names.push_back(ch->name);
  receiver.setChannelFilter(names);
}

ReceiveLosses Bus::receiveLosses() const {
  ReceiveLosses losses;
  for (const auto& entry : direct_) {
    const DirectReceiver& r = *entry.second;
    if (!r.filtered()) losses.overflowed_datagrams += r.kernelDrops();
    losses.incomplete_messages += r.incompleteMessages();
  }
  return losses;
}

std::uint64_t Bus::droppedMessages() const {
  std::uint64_t total = dropped_;
  for (const auto& entry : direct_) total += entry.second->malformed();
  return total;
}

std::uint64_t Bus::malformedDatagrams() const {
  std::uint64_t total = 0;
  for (const auto& entry : direct_) total += entry.second->malformed();
  return total;
}

std::uint64_t Bus::directDatagramsRead() const {
  std::uint64_t total = 0;
  for (const auto& entry : direct_) total += entry.second->datagramsRead();
  return total;
}

void Bus::addReceiver(lcm::LCM* lcm, DirectReceiver* direct, int fd) {
  for (const Receiver& r : receivers_)
    if (r.lcm == lcm && r.direct == direct) return;
  receivers_.push_back(Receiver{lcm, direct});
  poll_fds_.push_back(pollfd{fd, POLLIN, 0});
}

DirectReceiver& Bus::directReceiverFor(int offset) {
  for (auto& [o, receiver] : direct_)
    if (o == offset) return *receiver;
  direct_.emplace_back(offset, std::make_unique<DirectReceiver>(urlWithPortOffset(url_, offset)));
  return *direct_.back().second;
}

void Bus::drainAllDirect() {
  for (auto& entry : direct_) drainDirect(*entry.second);
  last_drain_ = std::chrono::steady_clock::now();
  dispatched_since_drain_ = 0;
}

void Bus::drainDirect(DirectReceiver& receiver) {
  receiver.drain([this](const DirectReceiver::Message& m) {
    for (auto& ch : channels_) {
      if (ch->name != m.channel) continue;
      if (ch->direct == nullptr || ch->subscribers.empty()) return;  // a channel nobody here listens to
      Queued q;
      q.channel = ch.get();
      if (!spare_buffers_.empty()) {
        q.data = std::move(spare_buffers_.back());
        spare_buffers_.pop_back();
      }
      q.data.assign(m.data, m.data + m.size);
      direct_queue_.push_back(std::move(q));
      return;
    }
  });
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
  if (receivers_.empty() || (receivers_.size() == 1 && receivers_.front().lcm != nullptr)) {
    // Nothing subscribed, or one LCM instance: LCM waits itself (one system call less than a poll first).
    lcm::LCM& only = receivers_.empty() ? *lcm_ : *receivers_.front().lcm;
    errno = 0;
    const int status = only.handleTimeout(static_cast<int>(timeout.count()));
    if (status < 0) {
      if (errno == EINTR) return false;  // a signal (SIGINT/SIGTERM) woke us: let the caller check its flag
      throw std::runtime_error("LCM handle failed");
    }
    rethrowPending();
    return status > 0;
  }
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (!direct_queue_.empty()) {
      // A backlog: read the sockets again every few messages or every millisecond, so that what
      // arrives meanwhile waits in our queue rather than filling a socket buffer (BusOptions).
      if (++dispatched_since_drain_ >= kBacklogDrainMessages ||
          std::chrono::steady_clock::now() - last_drain_ >= kBacklogDrainPeriod)
        drainAllDirect();
      Queued q = std::move(direct_queue_.front());
      direct_queue_.pop_front();
      dispatchQueued(q);
      rethrowPending();
      return true;
    }
    if (options_.min_wake_interval.count() > 0 && !direct_.empty()) {
      // Let what arrives meanwhile pile up in the sockets, to be read in one batch (BusOptions).
      const auto wake_at = std::min(last_drain_ + options_.min_wake_interval, deadline);
      if (std::chrono::steady_clock::now() < wake_at) std::this_thread::sleep_until(wake_at);
    }
    // Wait on every port at once, then handle one message of a ready one (round robin, so that a
    // busy port cannot starve another).
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    const int wait_ms = static_cast<int>(std::max<std::chrono::milliseconds::rep>(left.count(), 0));
    for (pollfd& p : poll_fds_) p.revents = 0;
    const int n = ::poll(poll_fds_.data(), poll_fds_.size(), wait_ms);
    if (n < 0) {
      if (errno == EINTR) return false;  // a signal (SIGINT/SIGTERM) woke us: let the caller check its flag
      throw std::runtime_error("LCM handle failed (poll)");
    }
    if (n == 0) return false;
    std::size_t ready = receivers_.size();
    for (std::size_t k = 0; k < receivers_.size(); ++k) {
      const std::size_t i = (next_receiver_ + k) % receivers_.size();
      if ((poll_fds_[i].revents & (POLLIN | POLLERR)) != 0) {
        ready = i;
        next_receiver_ = i + 1;
        break;
      }
    }
    if (ready == receivers_.size()) return false;  // only POLLHUP/POLLNVAL: nothing to read
    if (receivers_[ready].direct != nullptr) {
      drainDirect(*receivers_[ready].direct);
      last_drain_ = std::chrono::steady_clock::now();
      dispatched_since_drain_ = 0;
      if (direct_queue_.empty() && wait_ms == 0) return false;
      continue;  // a datagram nobody here listens to, or a fragment: wait for the rest
    }
    errno = 0;
    const int status = receivers_[ready].lcm->handleTimeout(0);
    if (status < 0) {
      if (errno == EINTR) return false;
      throw std::runtime_error("LCM handle failed");
    }
    rethrowPending();
    if (status > 0) return true;
    if (wait_ms == 0) return false;
  }
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
