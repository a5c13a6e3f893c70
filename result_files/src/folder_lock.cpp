#include "hunav/results/folder_lock.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "hunav/config_error.hpp"

namespace hunav::results {

namespace fs = std::filesystem;

namespace {

// What this process's FolderLocks hold: their folders and their descriptors.
std::mutex registry_mutex;
std::set<std::pair<dev_t, ino_t>> held_folders;
std::set<int> own_descriptors;

bool sameFile(int fd, const struct stat& folder) {
  struct stat st {};
  return ::fstat(fd, &st) == 0 && st.st_dev == folder.st_dev && st.st_ino == folder.st_ino;
}

// A descriptor this process inherited whose open file holds the lock on `folder` (flock on it
// succeeds: it is the holder's): a duplicate of it, else -1.
int inheritedLock(const struct stat& folder) {
  DIR* fds = ::opendir("/proc/self/fd");
  if (fds == nullptr) return -1;
  int found = -1;
  while (const dirent* entry = ::readdir(fds)) {
    char* end = nullptr;
    const long fd = std::strtol(entry->d_name, &end, 10);
    if (end == entry->d_name || *end != '\0' || fd == ::dirfd(fds) || own_descriptors.count(static_cast<int>(fd)) > 0)
      continue;
    if (sameFile(static_cast<int>(fd), folder) && ::flock(static_cast<int>(fd), LOCK_EX | LOCK_NB) == 0) {
      found = ::fcntl(static_cast<int>(fd), F_DUPFD_CLOEXEC, 0);
      break;
    }
  }
  ::closedir(fds);
  return found;
}

// The process holding the flock on `folder`, as /proc/locks lists it ("1: FLOCK ADVISORY WRITE PID
// MAJ:MIN:INODE 0 EOF"), or 0 when it cannot tell.
long holderOf(const struct stat& folder) {
  char device[64];
  std::snprintf(device, sizeof device, "%02x:%02x:%lu", ::major(folder.st_dev), ::minor(folder.st_dev),
                static_cast<unsigned long>(folder.st_ino));
  std::ifstream locks("/proc/locks");
  for (std::string line; std::getline(locks, line);) {
    if (line.find("FLOCK") == std::string::npos || line.find(std::string(" ") + device + " ") == std::string::npos)
      continue;
    char kind[16], advisory[16], mode[16];
    long pid = 0;
    if (std::sscanf(line.c_str(), "%*[^:]: %15s %15s %15s %ld", kind, advisory, mode, &pid) == 4) return pid;
  }
  return 0;
}

}  // namespace

FolderLock::FolderLock(const fs::path& dir) : dir_(dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("cannot open the folder " + dir.string() + ": " + std::strerror(errno));
  struct stat folder {};
  ::fstat(fd_, &folder);
  std::lock_guard<std::mutex> lock(registry_mutex);
  if (held_folders.count({folder.st_dev, folder.st_ino}) > 0) {
    ::close(fd_);
    throw ConfigError(dir.string(), 0, "--out",
                      "this process is writing into this folder already (one run per results folder at a time)");
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int inherited = errno == EWOULDBLOCK ? inheritedLock(folder) : -1;
    if (inherited < 0) {
      const long holder = holderOf(folder);
      ::close(fd_);
      throw ConfigError(dir.string(), 0, "--out",
                        "another run" + (holder > 0 ? " (process " + std::to_string(holder) + ")" : std::string()) +
                            " is writing into this folder: give each run a results folder of its own");
    }
    ::close(fd_);
    fd_ = inherited;
  }
  held_folders.insert({folder.st_dev, folder.st_ino});
  own_descriptors.insert(fd_);
}

FolderLock::~FolderLock() {
  std::lock_guard<std::mutex> lock(registry_mutex);
  struct stat folder {};
  if (::fstat(fd_, &folder) == 0) held_folders.erase({folder.st_dev, folder.st_ino});
  own_descriptors.erase(fd_);
  ::close(fd_);  // releases the lock (an inherited one stays with the process that handed it down)
}

}  // namespace hunav::results
