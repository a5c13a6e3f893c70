#pragma once
// The queue of messages a backend dispatches itself (InProcessBus, UdpmBus): channels with their
// subscribers, and messages waiting as boxed objects or bytes, with their storage recycled so that
// queuing the next message reuses it.
#include <deque>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "hunav/bus_backend.hpp"

namespace hunav::detail {

struct LocalChannel {
  std::string name;
  std::vector<Subscriber*> subscribers;            // null: ended while a message was being dispatched
  std::vector<std::unique_ptr<MessageBox>> spare;  // recycled boxes (a channel carries one type)
  int port_offset = 0;                             // UdpmBus: the port it travels on
};

struct QueuedMessage {
  LocalChannel* channel = nullptr;
  std::unique_ptr<MessageBox> box;  // a typed message, or
  std::vector<std::uint8_t> data;   // encoded bytes
};

class LocalQueue {
 public:
  // The channel called `name`, created on first use (a handful of channels: a linear search beats
  // hashing the name).
  LocalChannel& channel(std::string_view name) {
    for (auto& ch : channels_)
      if (ch->name == name) return *ch;
    channels_.push_back(std::make_unique<LocalChannel>());
    channels_.back()->name = std::string(name);
    return *channels_.back();
  }
  const std::vector<std::unique_ptr<LocalChannel>>& channels() const { return channels_; }

  void add(LocalChannel& ch, Subscriber& sub) { ch.subscribers.push_back(&sub); }
  void remove(Subscriber& sub) {
    for (auto& ch : channels_)
      for (Subscriber*& s : ch->subscribers)
        if (s == &sub) {
          s = nullptr;  // erased after the dispatch under way, if any
          removed_ = true;
        }
    if (dispatching_ == 0) compact();
  }
  static bool hasSubscribers(const LocalChannel& ch) {
    for (const Subscriber* s : ch.subscribers)
      if (s != nullptr) return true;
    return false;
  }

  bool empty() const { return queue_.empty(); }

  void pushBytes(LocalChannel& ch, const void* data, std::size_t size) {
    QueuedMessage q;
    q.channel = &ch;
    if (!spare_buffers_.empty()) {
      q.data = std::move(spare_buffers_.back());
      spare_buffers_.pop_back();
    }
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    q.data.assign(bytes, bytes + size);
    queue_.push_back(std::move(q));
  }

  // Queues a copy of the message, or swaps a given-up one in (its owner gets the recycled box's).
  void pushMessage(LocalChannel& ch, const OutgoingMessage& out) {
    std::unique_ptr<MessageBox> box;
    if (!ch.spare.empty() && ch.spare.back()->typeTag() == out.type) {
      box = std::move(ch.spare.back());
      ch.spare.pop_back();
    } else {
      box = out.type->new_box();
    }
    if (out.given_up != nullptr)
      out.type->swap_into(*box, out.given_up);
    else
      out.type->copy_into(*box, out.message);
    QueuedMessage q;
    q.channel = &ch;
    q.box = std::move(box);
    queue_.push_back(std::move(q));
  }

  // Takes the oldest message and gives it to each subscriber of its channel through
  // deliver(Subscriber&, const QueuedMessage&); then recycles its storage.
  template <class Deliver>
  void dispatchFront(Deliver&& deliver) {
    QueuedMessage q = std::move(queue_.front());
    queue_.pop_front();
    ++dispatching_;
    // By index: a handler may subscribe (and grow the list) while we dispatch.
    const std::size_t count = q.channel->subscribers.size();
    for (std::size_t i = 0; i < count; ++i)
      if (Subscriber* sub = q.channel->subscribers[i]; sub != nullptr) deliver(*sub, q);
    --dispatching_;
    if (dispatching_ == 0) compact();
    if (q.box)
      q.channel->spare.push_back(std::move(q.box));
    else
      spare_buffers_.push_back(std::move(q.data));
  }

 private:
  void compact() {
    if (!removed_) return;
    removed_ = false;
    for (auto& ch : channels_) {
      auto& subs = ch->subscribers;
      for (std::size_t i = 0; i < subs.size();)
        if (subs[i] == nullptr)
          subs.erase(subs.begin() + static_cast<std::ptrdiff_t>(i));
        else
          ++i;
    }
  }

  std::vector<std::unique_ptr<LocalChannel>> channels_;
  std::deque<QueuedMessage> queue_;
  std::vector<std::vector<std::uint8_t>> spare_buffers_;
  int dispatching_ = 0;
  bool removed_ = false;
};

}  // namespace hunav::detail
