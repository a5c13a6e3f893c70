#pragma once
// A small typed layer over lcm::LCM, shared by every process.
//  - subscribe() takes any callable; every subscription gets a queue capacity (unbounded by default,
//    because LCM's default of 30 silently drops the newest messages).
//  - A message that does not decode, or whose handler throws BadMessage, is dropped and counted.
//  - Any other exception thrown by a handler is caught before it crosses LCM's C code and rethrown
//    from handle*() to the caller.
// Two backends with the same semantics (FIFO over all channels, one message per handle):
//  - over an lcm::LCM (any URL: udpm between processes, memq:// in one process): encoded bytes;
//  - in-process (Bus::InProcess): a plain queue in this object, for the one-process runner. A message
//    published as a typed object reaches subscribers of its type as a copy of that object, without
//    encoding or decoding: LCM types round-trip exactly (every field is encoded, arrays as long as
//    their count fields, which receivers check), so handlers see what decoding would give them and
//    runs keep the fingerprints of an LCM run. Bytes (publishRaw) are decoded as over LCM.
// Channel ports: a udpm URL with our option `channel_ports=1` (removed before LCM sees the URL) puts
// the step protocol's channels on UDP ports of their own (channels::portOffset), one LCM instance per
// port. On one port every datagram wakes the receive thread of every process on the bus, the
// sender's own included, and the sender pays for each delivery: that is about half of the CPU and
// wall time of a lockstep tick (bench/bench_lcm_roundtrip.sh, bench/bench_lockstep.sh). An instance
// that only publishes never opens a receive socket, so a process no longer hears its own step
// messages either. Tools on the plain URL (lcm-spy, lcm-logger) then see every other channel.
// Subscriptions to those own-port channels do not go through LCM's receive path (a reader thread
// per instance that passes each datagram to the caller through a pipe: several system calls and two
// context switches per message) but through a socket of our own (DirectReceiver, transport.cpp),
// read in the calling thread. It speaks LCM's wire format, so LCM publishers, lcm-logger and lcm-spy
// on those ports interoperate with it.
#include <poll.h>

#include <chrono>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <hunav/wire_checks.hpp>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace hunav {

// Default bus: UDP multicast that never leaves this host (ttl=0), with a receive buffer large enough
// for world states of big crowds.
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

// URL precedence: the --lcm-url flag, then LCM_DEFAULT_URL, then kDefaultLcmUrl.
std::string resolveLcmUrl(const std::string& flag_value);

// The LCM URL a Bus opened on `url` uses for `channel`: `url` itself, or, for a udpm URL with
// `channel_ports=1`, the URL with the channel's port (the URL's, default 7667, plus
// channels::portOffset) and without that option. Throws std::invalid_argument for a bad port.
std::string lcmUrlForChannel(const std::string& url, std::string_view channel);

// Thrown by a handler that rejects a message it cannot use (NaN, impossible sizes, unknown ids).
struct BadMessage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class DirectReceiver;

// What one subscription dropped: messages that did not decode as its type, or that its handler
// rejected (BadMessage). Bus::subscribe returns it; it lives as long as the Bus.
struct SubscriptionDrops {
  std::uint64_t count = 0;
  std::string last_reason;  // why the last one was dropped (the BadMessage's text)
};

// How a Bus over a udpm URL receives (Bus(url, BusOptions)).
struct BusOptions {
  // Read the URL's own port with our direct receiver too, not only the step channels' ports (no LCM
  // reader thread, no pipe: the messages are read in the thread that calls handle*()). Nothing is
  // lost for it while the caller keeps calling handle*(): each wake-up reads every datagram waiting
  // (recvmmsg batches) into the bus's queue, and while that queue holds a backlog the socket is
  // drained again every few messages and every millisecond before the next dispatch (Bus::
  // kBacklogDrainMessages, kBacklogDrainPeriod), so the socket buffer (the
  // URL's recv_buf_size, which the default URL sets to 4 MB) only has to hold what arrives during
  // one handler call. Whatever is lost all the same (a handler that blocks longer than the buffer
  // covers) is counted: receiveLosses().
  // For the world, which publishes on that port every tick, its own datagrams then wait in the
  // socket until it next waits anyway (bench/bench_lockstep.sh: one context switch per tick less).
  bool direct_on_every_port = false;
  // With direct receivers: the kernel drops datagrams of channels nobody subscribes to through this
  // bus (a socket filter on each direct socket), so that they neither wake nor cost this process
  // anything (our planner process does not wake for each WORLD_STATE). The socket's overflow count
  // then includes those datagrams, so receiveLosses() cannot report overflows (reported as 0).
  // Fragments of long messages always pass the filter (only the first names its channel).
  bool filter_unsubscribed_channels = false;
  // With direct receivers: wake up at most once per interval (0: at every datagram). What arrives
  // meanwhile waits in the socket and is read in one batch, for a process that need not answer at
  // once (the evaluator: one wake-up per millisecond instead of one per tick). The socket buffer
  // must hold one interval's traffic.
  std::chrono::microseconds min_wake_interval{0};
};

// Messages our direct receivers lost (zeros for LCM's own receive path, which cannot tell).
struct ReceiveLosses {
  // Datagrams the kernel dropped because a socket's receive buffer was full (SO_MEMINFO's drop
  // count; without filter_unsubscribed_channels).
  std::uint64_t overflowed_datagrams = 0;
  // Fragmented messages abandoned because one of their fragments never arrived.
  std::uint64_t incomplete_messages = 0;
  bool any() const { return overflowed_datagrams != 0 || incomplete_messages != 0; }
};

class Bus {
 public:
  static constexpr int kUnbounded = 0;

  // Over an LCM instance the caller owns.
  explicit Bus(lcm::LCM& lcm);
  // Over LCM instances of its own on `url` (one per port with channel_ports=1). Throws when LCM
  // cannot be opened (bad URL, no multicast route).
  // direct_on_every_port: on a udpm URL, read the URL's own port with our direct receiver too, not
  // only the step channels' ports. For a process that publishes on that port every tick (the world):
  // its own datagrams then wait in the socket until it next waits anyway, instead of waking LCM's
  // reader thread each time (bench/bench_lockstep.sh: one context switch per tick less).
  explicit Bus(const std::string& url, bool direct_on_every_port = false);
  // The same with every receive option (BusOptions).
  Bus(const std::string& url, const BusOptions& options);
  struct InProcess {};
  explicit Bus(InProcess);
  ~Bus();
  Bus(const Bus&) = delete;
  Bus& operator=(const Bus&) = delete;

  // Returns the subscription's drop count (droppedMessages() counts it too), so that a component
  // sharing the bus with others (in process) can tell its own drops.
  template <class Msg, class Handler>
  const SubscriptionDrops& subscribe(std::string_view channel, Handler&& handler, int queue_capacity = kUnbounded) {
    auto sub =
        std::make_unique<TypedSubscription<Msg>>(this, std::function<void(const Msg&)>(std::forward<Handler>(handler)));
    const SubscriptionDrops& drops = sub->drops;
    attach(channel, std::move(sub), queue_capacity);
    return drops;
  }

  // Publishes `msg`: encoded over LCM, as a copy of the object in process.
  template <class Msg>
  void publish(std::string_view channel, const Msg& msg) {
    Channel& ch = channelFor(channel);
    if (dropForLossTest()) return;
    if (lcm_ != nullptr || tap_) {
      encode(msg);
      sendBytes(ch, buffer_.data(), buffer_.size());
    }
    if (lcm_ == nullptr) enqueueTyped(ch, msg);
  }

  // The same for a message the caller gives up (std::move(msg)): in process it is swapped into the
  // queue instead of copied, and `msg` is left holding a recycled message of the same type (valid,
  // contents unspecified: assign every field before using it again; its arrays keep their capacity).
  template <class Msg, class = std::enable_if_t<!std::is_lvalue_reference_v<Msg>>>
  void publish(std::string_view channel, Msg&& msg) {
    Channel& ch = channelFor(channel);
    if (dropForLossTest()) return;
    if (lcm_ != nullptr || tap_) {
      encode(msg);
      sendBytes(ch, buffer_.data(), buffer_.size());
    }
    if (lcm_ == nullptr) enqueueTaken(ch, msg);
  }

  // Publishes `msg` whose encoding the caller already has in `data` (e.g. from encode(), to hash it):
  // the bytes go over LCM, a copy of the object in process, as publish() does.
  template <class Msg>
  void publishEncoded(std::string_view channel, const Msg& msg, const void* data, std::size_t size) {
    Channel& ch = channelFor(channel);
    if (dropForLossTest()) return;
    sendBytes(ch, data, size);
    if (lcm_ == nullptr) enqueueTyped(ch, msg);
  }
  // The same for a message the caller gives up (std::move(msg)), as publish() of one.
  template <class Msg, class = std::enable_if_t<!std::is_lvalue_reference_v<Msg>>>
  void publishEncoded(std::string_view channel, Msg&& msg, const void* data, std::size_t size) {
    Channel& ch = channelFor(channel);
    if (dropForLossTest()) return;
    sendBytes(ch, data, size);
    if (lcm_ == nullptr) enqueueTaken(ch, msg);
  }

  // Encodes into an internal buffer and returns it (valid until the next encode/publish).
  template <class Msg>
  const std::vector<std::uint8_t>& encode(const Msg& msg) {
    const int size = msg.getEncodedSize();
    buffer_.resize(static_cast<std::size_t>(size));
    if (msg.encode(buffer_.data(), 0, size) != size) throw std::runtime_error("cannot encode a message");
    return buffer_;
  }

  // Publishes encoded bytes; subscribers decode them (a message that does not decode is dropped).
  void publishRaw(std::string_view channel, const void* data, std::size_t size);

  // Waits up to `timeout` for one message and dispatches it. Returns false on timeout.
  bool handleFor(std::chrono::milliseconds timeout);
  // Dispatches every message already waiting, without blocking.
  void handleAvailable();

  // Messages that did not decode or that a handler rejected, and datagrams not in LCM's format.
  std::uint64_t droppedMessages() const;
  // Of those, the datagrams our direct receivers read that are not in LCM's format (no channel, so
  // no subscription's).
  std::uint64_t malformedDatagrams() const;
  // What our direct receivers lost so far (asks the kernel for each socket's drop count).
  ReceiveLosses receiveLosses() const;
  // Datagrams our direct receivers read (those a socket filter dropped never count).
  std::uint64_t directDatagramsRead() const;
  // While handle*() dispatches a backlog of messages read by direct receivers, it reads the sockets
  // again at least after this many messages and after this long.
  static constexpr int kBacklogDrainMessages = 8;
  static constexpr std::chrono::milliseconds kBacklogDrainPeriod{1};
  bool inProcess() const { return lcm_ == nullptr; }

  // Sees every message published through this bus, encoded (for recording a log of an in-process run).
  using Tap = std::function<void(const std::string& channel, const void* data, std::size_t size)>;
  void setTap(Tap tap) { tap_ = std::move(tap); }

  // Test hook: drop each outgoing message with this probability (seeded, reproducible), to prove the
  // protocol survives loss. 0 disables it.
  void setOutgoingLossForTesting(double probability, std::uint64_t seed);
  std::uint64_t lostForTesting() const { return lost_for_testing_; }

 private:
  // A typed message waiting in the in-process queue; recycled per channel, so that copying the next
  // message into it reuses its arrays and strings.
  struct Box {
    virtual ~Box() = default;
    virtual const void* typeTag() const = 0;
    virtual void encodeTo(std::vector<std::uint8_t>& out) const = 0;
  };
  template <class Msg>
  struct TypedBox final : Box {
    static constexpr char kTag = 0;  // its address identifies Msg
    const void* typeTag() const override { return &kTag; }
    void encodeTo(std::vector<std::uint8_t>& out) const override {
      out.resize(static_cast<std::size_t>(msg.getEncodedSize()));
      msg.encode(out.data(), 0, static_cast<int>(out.size()));
    }
    Msg msg;
  };

  struct Subscription {
    virtual ~Subscription() = default;
    void onRaw(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
    // Runs the handler; a BadMessage is counted, any other exception kept for the caller.
    void deliver(const void* data, unsigned size);
    void deliver(const Box& box);
    void drop(const char* reason) {
      ++bus->dropped_;
      ++drops.count;
      drops.last_reason = reason;
    }
    virtual void dispatch(const void* data, unsigned size) = 0;
    // False when the box holds another type than this subscription's.
    virtual bool dispatchBox(const Box& box) = 0;
    Bus* bus = nullptr;
    lcm::Subscription* handle = nullptr;  // LCM backend: the subscription and its instance
    lcm::LCM* lcm = nullptr;
    SubscriptionDrops drops;
  };
  static constexpr const char* kUndecodable = "a message that does not decode as the channel's type";
  template <class Msg>
  struct TypedSubscription final : Subscription {
    TypedSubscription(Bus* b, std::function<void(const Msg&)> h) : handler(std::move(h)) { bus = b; }
    void dispatch(const void* data, unsigned size) override {
      // A fresh message every time: LCM 1.3.1's decoders leave a primitive array untouched when its
      // count is 0, so a reused message would keep the previous one's elements.
      // lcm-gen's decoder trusts string lengths and array counts (a bad one crashes or allocates
      // gigabytes): the bytes are checked first (lcmtypes/gen_wire_checks.py).
      if (!wire::safeToDecode<Msg>(data, size)) {
        drop(kUndecodable);
        return;
      }
      Msg msg;
      int decoded = -1;
      try {
        decoded = msg.decode(data, 0, static_cast<int>(size));
      } catch (const std::exception&) {
        decoded = -1;
      }
      if (decoded < 0) {
        drop(kUndecodable);
        return;
      }
      handler(msg);
    }
    bool dispatchBox(const Box& box) override {
      if (box.typeTag() != &TypedBox<Msg>::kTag) return false;
      handler(static_cast<const TypedBox<Msg>&>(box).msg);
      return true;
    }
    std::function<void(const Msg&)> handler;
  };

  struct Channel {
    std::string name;
    lcm::LCM* lcm = nullptr;                  // LCM backend: the instance of its port
    DirectReceiver* direct = nullptr;         // LCM backend: our receive socket of its own port
    std::vector<Subscription*> subscribers;   // in-process backend, and direct receivers
    std::vector<std::unique_ptr<Box>> spare;  // recycled boxes (a channel carries one type)
  };
  struct Queued {
    Channel* channel = nullptr;
    std::unique_ptr<Box> box;        // a typed message, or
    std::vector<std::uint8_t> data;  // encoded bytes
  };

  Channel& channelFor(std::string_view name);
  void attach(std::string_view channel, std::unique_ptr<Subscription> sub, int queue_capacity);
  // Draws from the loss test hook: true when this message is to be dropped.
  bool dropForLossTest();
  // Shows encoded bytes to the tap and, over LCM, publishes them.
  void sendBytes(Channel& ch, const void* data, std::size_t size);
  template <class Msg>
  void enqueueTyped(Channel& ch, const Msg& msg) {
    if (ch.subscribers.empty()) return;  // as LCM: a message nobody subscribes to is not queued
    TypedBox<Msg>& box = nextBox<Msg>(ch);
    box.msg = msg;
  }
  // Swaps `msg` into the queue (the caller gets the recycled box's message).
  template <class Msg>
  void enqueueTaken(Channel& ch, Msg& msg) {
    if (ch.subscribers.empty()) return;
    TypedBox<Msg>& box = nextBox<Msg>(ch);
    using std::swap;
    swap(box.msg, msg);
  }
  // Queues a box for Msg on `ch` (a recycled one when there is one) and returns it.
  template <class Msg>
  TypedBox<Msg>& nextBox(Channel& ch) {
    std::unique_ptr<Box> box;
    if (!ch.spare.empty() && ch.spare.back()->typeTag() == &TypedBox<Msg>::kTag) {
      box = std::move(ch.spare.back());
      ch.spare.pop_back();
    } else {
      box = std::make_unique<TypedBox<Msg>>();
    }
    auto& typed = static_cast<TypedBox<Msg>&>(*box);
    Queued q;
    q.channel = &ch;
    q.box = std::move(box);
    queue_.push_back(std::move(q));
    return typed;
  }
  void dispatchQueued(Queued& q);
  void rethrowPending();

  // The instance of `offset`'s port, opened on first use.
  lcm::LCM& instanceFor(int offset);
  // Our own receive socket of `offset`'s port, opened on first use.
  DirectReceiver& directReceiverFor(int offset);
  // Reads what the ready direct receiver has and queues the messages subscribed to.
  void drainDirect(DirectReceiver& receiver);
  // Reads every direct receiver without waiting (a backlog is being dispatched: keep the sockets empty).
  void drainAllDirect();
  // The channels subscribed to through `receiver`, for its socket filter.
  void updateFilter(DirectReceiver& receiver);
  void addReceiver(lcm::LCM* lcm, DirectReceiver* direct, int fd);

  lcm::LCM* lcm_ = nullptr;  // null: in-process backend; else the instance of the URL's port
  std::string url_;          // with channel ports: the URL the per-port instances derive from
  bool channel_ports_ = false;
  BusOptions options_;
  std::chrono::steady_clock::time_point last_drain_{};  // of every direct receiver
  int dispatched_since_drain_ = 0;
  std::vector<std::pair<int, std::unique_ptr<lcm::LCM>>> owned_;  // port offset, instance
  // What handle*() waits on: LCM instances with subscriptions and our direct receivers.
  struct Receiver {
    lcm::LCM* lcm = nullptr;
    DirectReceiver* direct = nullptr;
  };
  std::vector<Receiver> receivers_;
  std::vector<std::pair<int, std::unique_ptr<DirectReceiver>>> direct_;  // port offset, receiver
  std::deque<Queued> direct_queue_;  // messages read by direct receivers, not yet dispatched
  std::vector<pollfd> poll_fds_;
  std::size_t next_receiver_ = 0;  // round robin among ready instances
  std::vector<std::unique_ptr<Channel>> channels_;
  std::deque<Queued> queue_;
  std::vector<std::vector<std::uint8_t>> spare_buffers_;  // recycled, so queuing does not allocate
  std::vector<std::uint8_t> convert_buffer_;              // a box encoded for a subscriber of another type
  Tap tap_;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;
  std::vector<std::uint8_t> buffer_;
  std::exception_ptr pending_;
  std::uint64_t dropped_ = 0;
  double loss_probability_ = 0.0;
  std::uint64_t loss_state_ = 0;
  std::uint64_t lost_for_testing_ = 0;
};

}  // namespace hunav
