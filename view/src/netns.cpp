#include "hunav/view/netns.hpp"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace hunav::view {

namespace {
ino_t nsInode(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return 0;
  return st.st_ino;
}

void join(const std::string& path, int type, const char* what) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(std::string("cannot open ") + path + ": " + std::strerror(errno));
  const int rc = ::setns(fd, type);
  const int err = errno;
  ::close(fd);
  if (rc != 0)
    throw std::runtime_error(std::string("cannot join the ") + what + " namespace " + path + ": " + std::strerror(err));
}
}  // namespace

bool multicastRouted() {
  // /proc/thread-self/net/route: Iface, Destination, Gateway, Flags, RefCnt, Use, Metric, Mask, ...
  // with addresses in hex, in the host's (little-endian) byte order: 224.0.0.0/4 is 000000E0/000000F0.
  std::ifstream in("/proc/thread-self/net/route");
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string iface, destination, gateway, flags, refcnt, use, metric, mask;
    fields >> iface >> destination >> gateway >> flags >> refcnt >> use >> metric >> mask;
    if (destination == "000000E0" && mask == "000000F0") return true;
  }
  return false;
}

bool processAlive(pid_t pid) { return ::kill(pid, 0) == 0 || errno == EPERM; }

void joinNetworkNamespaceOf(pid_t pid, std::chrono::milliseconds timeout) {
  const std::string base = "/proc/" + std::to_string(pid) + "/ns/";
  const ino_t ours = nsInode("/proc/thread-self/ns/net");
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (!processAlive(pid)) throw std::runtime_error("process " + std::to_string(pid) + " has exited");
    const ino_t theirs = nsInode(base + "net");
    if (theirs != 0 && theirs != ours) break;
    if (std::chrono::steady_clock::now() > deadline)
      throw std::runtime_error("process " + std::to_string(pid) + " did not enter a network namespace of its own");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // Without root, the run's namespace belongs to a user namespace of its own (unshare -rn): enter it
  // first (its creator's uid holds every capability there).
  if (nsInode(base + "user") != nsInode("/proc/thread-self/ns/user")) {
    try {
      join(base + "net", CLONE_NEWNET, "network");
      return;
    } catch (const std::runtime_error&) {
      join(base + "user", CLONE_NEWUSER, "user");
    }
  }
  join(base + "net", CLONE_NEWNET, "network");
}

}  // namespace hunav::view
