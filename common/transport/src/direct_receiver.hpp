#pragma once
// A receive socket on one udpm port, read in the caller's thread, in LCM's wire format (UdpmBus).
#include <arpa/inet.h>
#include <linux/filter.h>
#include <linux/sock_diag.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <deque>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace hunav::detail {

// The parts of a udpm URL our receive socket needs.
struct UdpmEndpoint {
  in_addr group{};
  int port = 7667;        // LCM's default
  int recv_buf_size = 0;  // 0: the system's default
};

inline UdpmEndpoint parseUdpm(const std::string& url) {
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

inline std::uint32_t bigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
inline std::uint16_t bigEndian16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }

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
  // A channel with an entry `every` > 1 in `sample_every` passes each short message with probability
  // 1 / `every` (the kernel's per-packet random number: a publisher's sequence numbers could fall
  // into a pattern that a modulus would always miss).
  void setChannelFilter(const std::vector<std::string>& channels,
                        const std::map<std::string, std::uint32_t>& sample_every = {}) {
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
      const auto sampled = sample_every.find(name);
      const std::uint32_t every = sampled == sample_every.end() ? 1 : sampled->second;
      // Instructions of the block: per word a load, a compare and, for a partial last word, a mask;
      // then the accept (or, sampled: a random number modulo `every`, accept a zero, drop the rest).
      // A mismatch jumps past the rest of the block.
      const std::size_t ending = every > 1 ? 5 : 1;
      const std::size_t block = words * 2 + (tail != 0 ? 1 : 0) + ending;
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
            done + (words - 1 - w) * 2 + ending + ((tail != 0 && w + 1 < words) ? 1 : 0);  // the ending included
        program.push_back(BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, value, 0, static_cast<std::uint8_t>(block_end - done)));
      }
      if (every > 1) {
        program.push_back(BPF_STMT(BPF_LD | BPF_W | BPF_ABS, static_cast<std::uint32_t>(SKF_AD_OFF + SKF_AD_RANDOM)));
        program.push_back(BPF_STMT(BPF_ALU | BPF_MOD | BPF_K, every));
        program.push_back(BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, 0, 0, 1));
        program.push_back(BPF_STMT(BPF_RET | BPF_K, kAccept));
        program.push_back(BPF_STMT(BPF_RET | BPF_K, kDrop));
      } else {
        program.push_back(BPF_STMT(BPF_RET | BPF_K, kAccept));
      }
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
}  // namespace hunav::detail
