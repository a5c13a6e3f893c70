#pragma once
// One writer per results folder. A run holds an exclusive lock on its folder for as long as it writes
// there, so that two runs into one --out at once (they tore states.csv, and both exited 0) cannot
// happen: the second is refused before it starts (ConfigError: exit 2, "another run is writing into
// DIR"). The lock is flock(2) on the folder itself: nothing is added to the folder, and the kernel
// releases it when the process ends, however it ends (a killed run leaves no stale lock).
// One process holds a folder once (a second FolderLock on it, from any thread, is refused). A process
// started by one that holds the lock takes it over on the descriptor it inherited
// (run_experiment.sh holds its --out for the whole run; the hunav_run or hunav_evaluator it starts
// writes there under that lock).
#include <filesystem>

namespace hunav::results {

class FolderLock {
 public:
  // Creates `dir` when missing and locks it. Throws ConfigError(dir, 0, "--out", ...) when another
  // process, or another FolderLock of this one, holds it; std::runtime_error when it cannot be opened.
  explicit FolderLock(const std::filesystem::path& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  int fd_ = -1;
};

}  // namespace hunav::results
