// One writer per results folder (issue 31: two runs into one --out at once both exited 0 and tore
// states.csv). The lock refuses a second writer in this process or another, names the process that
// holds it, is released when its holder ends, and passes to a process started by its holder.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <thread>

#include "config_error_of.hpp"
#include "hunav/results/folder_lock.hpp"
#include "hunav/testing/temp_dir.hpp"

using hunav::results::FolderLock;
using result_files_test::configErrorOf;

namespace {

// Runs `child` in a forked process; returns its exit status (what child() returned).
template <class Child>
int inChild(Child child) {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(child());
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

TEST(FolderLock, ASecondWriterOfThisProcessIsRefusedUntilTheFirstEnds) {
  const auto dir = hunav::testing::testDir().path() / "out";
  {
    const FolderLock first(dir);  // creates the folder
    EXPECT_TRUE(std::filesystem::is_directory(dir));
    const std::string refused = configErrorOf([&] { FolderLock second(dir); });
    EXPECT_NE(refused.find(dir.string()), std::string::npos) << refused;
    EXPECT_NE(refused.find("writing into this folder already"), std::string::npos) << refused;
    // From another thread too (hunav_view's editor runs two runs at once).
    std::string from_thread;
    std::thread([&] { from_thread = configErrorOf([&] { FolderLock again(dir); }); }).join();
    EXPECT_FALSE(from_thread.empty());
  }
  EXPECT_EQ(configErrorOf([&] { FolderLock after(dir); }), "");
  EXPECT_TRUE(std::filesystem::is_empty(dir));  // nothing added to the folder
}

TEST(FolderLock, AnotherProcessIsRefusedAndToldWhoHoldsIt) {
  const auto dir = hunav::testing::testDir().path() / "out";
  int to_child[2], from_child[2];
  ASSERT_EQ(::pipe(to_child), 0);
  ASSERT_EQ(::pipe(from_child), 0);
  const pid_t holder = ::fork();
  if (holder == 0) {
    const FolderLock lock(dir);
    char c = 'l';
    (void)!::write(from_child[1], &c, 1);
    (void)!::read(to_child[0], &c, 1);  // until the parent says
    ::_exit(0);
  }
  char c = 0;
  ASSERT_EQ(::read(from_child[0], &c, 1), 1);
  const std::string refused = configErrorOf([&] { FolderLock mine(dir); });
  EXPECT_NE(refused.find("another run (process " + std::to_string(holder) + ") is writing into this folder"),
            std::string::npos)
      << refused;
  (void)!::write(to_child[1], &c, 1);
  int status = 0;
  ::waitpid(holder, &status, 0);
  EXPECT_EQ(configErrorOf([&] { FolderLock mine(dir); }), "");  // released with its holder
  // Killed while holding it: released all the same (no stale lock).
  const int killed = inChild([&] {
    const FolderLock lock(dir);
    ::kill(::getpid(), SIGKILL);
    return 0;
  });
  EXPECT_EQ(killed, 128 + SIGKILL);
  EXPECT_EQ(configErrorOf([&] { FolderLock mine(dir); }), "");
}

TEST(FolderLock, AProcessStartedByTheHolderTakesItOver) {
  // As run_experiment.sh: the script holds the folder on a descriptor its children inherit.
  const auto dir = hunav::testing::testDir().path() / "out";
  std::filesystem::create_directories(dir);
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  EXPECT_EQ(inChild([&] { return configErrorOf([&] { FolderLock child(dir); }).empty() ? 0 : 1; }), 0);
  // A process that did not inherit it (its descriptor closed) is refused.
  EXPECT_EQ(inChild([&] {
              ::close(fd);
              return configErrorOf([&] { FolderLock child(dir); }).empty() ? 0 : 1;
            }),
            1);
  ::close(fd);
}
