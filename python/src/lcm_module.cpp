// _lcm: LCM's Python API (lcm.LCM, lcm.LCMSubscription and the event log reader/writer under
// lcm.EventLog) over Debian's liblcm, for Debian's Python, which has no python3-lcm. The API is
// upstream LCM's (lcm-python), so LCM Python programs run unchanged; python/lcm/__init__.py adds the
// pure-Python part (Event, EventLog). python/README.md, "LCM in Python".
#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <poll.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

// Raises OSError(what) in Python (upstream LCM raises IOError, its alias).
[[noreturn]] void throwOsError(const std::string& what) {
  PyErr_SetString(PyExc_OSError, what.c_str());
  throw py::error_already_set();
}

class Lcm;

// One subscription: the Python handler called with (channel, data) for each message on the channel
// (a regular expression, as in LCM).
class Subscription {
 public:
  Subscription(Lcm* owner, std::string channel, py::object handler)
      : owner_(owner), channel_(std::move(channel)), handler_(std::move(handler)) {}

  void setQueueCapacity(int messages);
  const std::string& channel() const { return channel_; }

  Lcm* owner_;  // null once unsubscribed (or its LCM is gone)
  lcm_subscription_t* handle_ = nullptr;
  std::string channel_;
  py::object handler_;
};

// Messages arrive on liblcm's reader thread; liblcm hands them over through a file descriptor
// (fileno()). We wait on it without the GIL (other Python threads run, Ctrl-C is heard), then
// dispatch with the GIL held, so handlers run as ordinary Python code on the calling thread.
class Lcm {
 public:
  explicit Lcm(const std::optional<std::string>& url) {
    const std::string provider = url.value_or("");
    lcm_ = lcm_create(provider.empty() ? nullptr : provider.c_str());
    if (lcm_ == nullptr)
      throw std::runtime_error("Couldn't create LCM" + (provider.empty() ? std::string() : " for '" + provider + "'"));
  }
  ~Lcm() {
    for (auto& sub : subscriptions_) sub->owner_ = nullptr;
    if (lcm_ != nullptr) lcm_destroy(lcm_);
  }
  Lcm(const Lcm&) = delete;
  Lcm& operator=(const Lcm&) = delete;

  void publish(const std::string& channel, const py::buffer& data) {
    const py::buffer_info info = data.request();
    if (info.ndim > 1 && !isContiguous(info)) throw py::value_error("publish: the data must be contiguous bytes");
    const auto size = static_cast<std::size_t>(info.size * info.itemsize);
    if (size > static_cast<std::size_t>(INT32_MAX)) throw py::value_error("publish: the data is too large");
    int status;
    {
      py::gil_scoped_release nogil;  // `data` stays referenced by the caller's frame
      status = lcm_publish(lcm_, channel.c_str(), info.ptr, static_cast<unsigned int>(size));
    }
    if (status != 0) throwOsError("LCM publish failed");
  }

  std::shared_ptr<Subscription> subscribe(const std::string& channel, py::object handler) {
    if (!PyCallable_Check(handler.ptr())) throw py::type_error("subscribe: the handler must be callable");
    auto sub = std::make_shared<Subscription>(this, channel, std::move(handler));
    sub->handle_ = lcm_subscribe(lcm_, channel.c_str(), &Lcm::onMessage, sub.get());
    if (sub->handle_ == nullptr) throwOsError("LCM subscribe failed for '" + channel + "'");
    subscriptions_.push_back(sub);
    return sub;
  }

  void unsubscribe(const std::shared_ptr<Subscription>& sub) {
    if (!sub || sub->owner_ != this) throw py::value_error("unsubscribe: not a subscription of this LCM instance");
    lcm_unsubscribe(lcm_, sub->handle_);
    sub->owner_ = nullptr;
    sub->handle_ = nullptr;
    // The handler may be running now (unsubscribing itself): onMessage holds its own reference.
    subscriptions_.erase(std::remove(subscriptions_.begin(), subscriptions_.end(), sub), subscriptions_.end());
  }

  int fileno() const { return lcm_get_fileno(lcm_); }

  // Waits for a message (forever) and dispatches it.
  void handle() {
    ReentryGuard guard(*this);
    while (!waitReadable(-1)) {
    }
    dispatch();
  }

  // Waits up to timeout_ms for a message: 1 when one was dispatched, 0 on timeout.
  int handleTimeout(int timeout_ms) {
    if (timeout_ms < 0) throw py::value_error("handle_timeout: the timeout must be >= 0 ms");
    ReentryGuard guard(*this);
    if (!waitReadable(timeout_ms)) return 0;
    dispatch();
    return 1;
  }

 private:
  // handle() from two threads at once would make the second read a descriptor the first emptied,
  // blocking with the GIL held: refused instead.
  struct ReentryGuard {
    explicit ReentryGuard(Lcm& l) : lcm(l) {
      if (lcm.handling_)
        throw std::runtime_error(
            "LCM.handle: another thread (or a handler) is already handling messages of this LCM instance");
      lcm.handling_ = true;
    }
    ~ReentryGuard() { lcm.handling_ = false; }
    Lcm& lcm;
  };

  static bool isContiguous(const py::buffer_info& info) {
    py::ssize_t expected = info.itemsize;
    for (py::ssize_t d = info.ndim - 1; d >= 0; --d) {
      if (info.strides[static_cast<std::size_t>(d)] != expected) return false;
      expected *= info.shape[static_cast<std::size_t>(d)];
    }
    return true;
  }

  // True when the descriptor became readable within timeout_ms (-1: no limit). Waits in slices of
  // at most 100 ms, running Python's signal handlers between them (KeyboardInterrupt propagates), so
  // Ctrl-C is heard whichever thread the kernel delivered SIGINT to.
  bool waitReadable(int timeout_ms) {
    using std::chrono::steady_clock;
    const auto deadline = steady_clock::now() + std::chrono::milliseconds(std::max(timeout_ms, 0));
    for (;;) {
      int slice = 100;
      if (timeout_ms >= 0) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - steady_clock::now());
        slice = static_cast<int>(std::clamp<std::int64_t>(left.count(), 0, 100));
      }
      pollfd p{fileno(), POLLIN, 0};
      int r;
      int err;
      {
        py::gil_scoped_release nogil;
        r = ::poll(&p, 1, slice);
        err = errno;
      }
      if (r > 0) return true;
      if (r < 0 && err != EINTR) throwOsError(std::string("LCM: poll failed: ") + std::strerror(err));
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (r == 0 && timeout_ms >= 0 && steady_clock::now() >= deadline) return false;
    }
  }

  void dispatch() {
    const int status = lcm_handle(lcm_);
    if (pending_) {
      auto error = std::move(*pending_);
      pending_.reset();
      throw error;  // the handler's exception, as upstream LCM raises it from handle()
    }
    if (status != 0) throwOsError("lcm_handle() returned -1");
  }

  static void onMessage(const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
    auto* sub = static_cast<Subscription*>(user);
    Lcm* lcm = sub->owner_;
    if (lcm == nullptr) return;
    py::object handler = sub->handler_;  // alive even if the handler unsubscribes itself
    if (lcm->pending_) return;           // one exception per handle(): later messages wait for the next
    try {
      handler(py::str(channel), py::bytes(static_cast<const char*>(rbuf->data), rbuf->data_size));
    } catch (py::error_already_set& e) {
      lcm->pending_.emplace(std::move(e));
    }
  }

  lcm_t* lcm_ = nullptr;
  std::vector<std::shared_ptr<Subscription>> subscriptions_;
  std::optional<py::error_already_set> pending_;
  bool handling_ = false;
};

void Subscription::setQueueCapacity(int messages) {
  if (owner_ == nullptr) throw py::value_error("set_queue_capacity: the subscription has ended");
  if (messages < 0) throw py::value_error("set_queue_capacity: the capacity must be >= 0 (0: unbounded)");
  if (lcm_subscription_set_queue_capacity(handle_, messages) != 0)
    throw std::runtime_error("lcm_subscription_set_queue_capacity failed");
}

// The low-level event log (lcm.EventLog wraps it): LCM's log file format through liblcm.
class EventLog {
 public:
  EventLog(const std::string& path, const std::string& mode) : path_(path), mode_(mode) {
    if (mode != "r" && mode != "w" && mode != "a") throw py::value_error("EventLog: mode must be 'r', 'w' or 'a'");
    log_ = lcm_eventlog_create(path.c_str(), mode.c_str());
    if (log_ == nullptr) {
      PyErr_SetFromErrnoWithFilename(PyExc_OSError, path.c_str());
      throw py::error_already_set();
    }
  }
  ~EventLog() { close(); }
  EventLog(const EventLog&) = delete;
  EventLog& operator=(const EventLog&) = delete;

  void close() {
    if (log_ != nullptr) lcm_eventlog_destroy(log_);
    log_ = nullptr;
  }

  // (eventnum, timestamp, channel, data), or None at the end of the log.
  py::object readNextEvent() {
    require('r', "read_next_event");
    lcm_eventlog_event_t* e = lcm_eventlog_read_next_event(log_);
    if (e == nullptr) return py::none();
    py::tuple out = py::make_tuple(
        e->eventnum, e->timestamp,
        py::reinterpret_steal<py::object>(PyUnicode_DecodeUTF8(e->channel, e->channellen, "surrogateescape")),
        py::bytes(static_cast<const char*>(e->data), static_cast<std::size_t>(e->datalen)));
    lcm_eventlog_free_event(e);
    return std::move(out);
  }

  void writeEvent(std::int64_t utime, const std::string& channel, const py::buffer& data) {
    require('w', "write_event");
    const py::buffer_info info = data.request();
    const auto size = info.size * info.itemsize;
    if (channel.size() > 255) throw py::value_error("write_event: a channel name has at most 255 bytes");
    if (size > INT32_MAX) throw py::value_error("write_event: the data is too large");
    lcm_eventlog_event_t e{};
    e.timestamp = utime;
    e.channellen = static_cast<std::int32_t>(channel.size());
    e.datalen = static_cast<std::int32_t>(size);
    e.channel = const_cast<char*>(channel.c_str());
    e.data = info.ptr;
    if (lcm_eventlog_write_event(log_, &e) != 0) throwOsError("write_event failed");
  }

  void seek(std::int64_t offset) {
    require('r', "seek");
    if (fseeko(log_->f, offset, SEEK_SET) != 0) throwOsError("seek failed");
  }
  void seekToTimestamp(std::int64_t timestamp) {
    require('r', "seek_to_timestamp");
    if (lcm_eventlog_seek_to_timestamp(log_, timestamp) != 0) throwOsError("seek_to_timestamp failed");
  }
  std::int64_t size() const {
    struct stat st {};
    if (::stat(path_.c_str(), &st) != 0) throwOsError("size: cannot stat " + path_);
    return st.st_size;
  }
  std::int64_t tell() const {
    requireOpen("tell");
    return ftello(log_->f);
  }

 private:
  void requireOpen(const char* what) const {
    if (log_ == nullptr) throw py::value_error(std::string(what) + ": the event log is closed");
  }
  void require(char mode, const char* what) const {
    requireOpen(what);
    const bool writing = mode_ != "r";
    if ((mode == 'w') != writing)
      throw std::runtime_error(std::string(what) + ": the event log is open for " + (writing ? "writing" : "reading"));
  }

  std::string path_;
  std::string mode_;
  lcm_eventlog_t* log_ = nullptr;
};

}  // namespace

PYBIND11_MODULE(_lcm, m) {
  m.doc() = "LCM's Python API over liblcm (python/README.md, \"LCM in Python\")";

  py::class_<Subscription, std::shared_ptr<Subscription>>(m, "LCMSubscription")
      .def("set_queue_capacity", &Subscription::setQueueCapacity, py::arg("num_messages"),
           "How many messages may wait for handle() on this subscription (0: unbounded); LCM drops "
           "the newest beyond it")
      .def_property_readonly("channel", &Subscription::channel);

  py::class_<Lcm>(m, "LCM")
      .def(py::init<std::optional<std::string>>(), py::arg("provider") = py::none(),
           "LCM on `provider` (an LCM URL; default $LCM_DEFAULT_URL, else LCM's default)")
      .def("publish", &Lcm::publish, py::arg("channel"), py::arg("data"))
      .def("subscribe", &Lcm::subscribe, py::arg("channel"), py::arg("callback"),
           "Calls callback(channel, data) for each message on the channels matching `channel` (a "
           "regular expression), from handle()/handle_timeout()")
      .def("unsubscribe", &Lcm::unsubscribe, py::arg("subscription_object"))
      .def("handle", &Lcm::handle, "Waits for one message and dispatches it")
      .def("handle_timeout", &Lcm::handleTimeout, py::arg("timeout_millis"),
           "Waits up to timeout_millis for one message and dispatches it: 1 if one was, 0 on timeout")
      .def("fileno", &Lcm::fileno, "A file descriptor that is readable when a message waits");

  py::class_<EventLog>(m, "EventLog")
      .def(py::init<const std::string&, const std::string&>(), py::arg("path"), py::arg("mode") = "r")
      .def("close", &EventLog::close)
      .def("read_next_event", &EventLog::readNextEvent)
      .def("write_event", &EventLog::writeEvent, py::arg("utime"), py::arg("channel"), py::arg("data"))
      .def("seek", &EventLog::seek, py::arg("filepos"))
      .def("seek_to_timestamp", &EventLog::seekToTimestamp, py::arg("timestamp"))
      .def("size", &EventLog::size)
      .def("tell", &EventLog::tell);
}
