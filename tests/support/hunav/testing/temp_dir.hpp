#pragma once
// The one temporary folder of the tests: unique even when two copies of a test binary run at once
// (mkdtemp), removed with everything in it when it goes away. A folder of a failed test is kept and
// its path printed, to look at what the test wrote (HUNAV_KEEP_TEMP=1 keeps every folder).
#include <filesystem>
#include <string>

namespace hunav::testing {

class TempDir {
 public:
  // A new empty folder under the system's temporary directory, named after the running test
  // (suite.name) and `tag`.
  explicit TempDir(const std::string& tag = "");
  ~TempDir();
  TempDir(TempDir&& other) noexcept;
  TempDir& operator=(TempDir&& other) noexcept;
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string string() const { return path_.string(); }
  std::filesystem::path operator/(const std::filesystem::path& rel) const { return path_ / rel; }
  operator const std::filesystem::path&() const { return path_; }  // NOLINT: used where a path is

  // An empty folder `name` inside this one (emptied if it exists), for tests that need several.
  std::filesystem::path subdir(const std::filesystem::path& name) const;

 private:
  friend class TestDirListener;
  void release(bool keep);

  std::filesystem::path path_;
};

// The running test's folder, made on first use and removed when the test ends (kept if it failed):
// for helpers that write files on behalf of whichever test calls them.
TempDir& testDir();

}  // namespace hunav::testing
