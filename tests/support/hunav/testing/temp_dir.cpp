#include "hunav/testing/temp_dir.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

namespace hunav::testing {

namespace {

// suite.name[_tag] with only [A-Za-z0-9._-] (parameterised tests have '/'), short enough for a name.
std::string folderName(const std::string& tag) {
  std::string name = "hunav";
  if (const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info())
    name += std::string("_") + info->test_suite_name() + "." + info->name();
  if (!tag.empty()) name += "_" + tag;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-' && c != '_') c = '_';
  if (name.size() > 120) name.resize(120);
  return name + ".XXXXXX";
}

// HUNAV_KEEP_TEMP=1 keeps every folder, to look at what passing tests wrote.
bool keepAll() {
  const char* keep = std::getenv("HUNAV_KEEP_TEMP");
  return keep != nullptr && std::string(keep) == "1";
}

std::unique_ptr<TempDir>& runningTestDir() {
  static std::unique_ptr<TempDir> dir;
  return dir;
}

}  // namespace

// Ends the running test's folder with the test, keeping it when the test failed.
class TestDirListener : public ::testing::EmptyTestEventListener {
 public:
  void OnTestEnd(const ::testing::TestInfo& info) override {
    if (!runningTestDir()) return;
    runningTestDir()->release(info.result()->Failed());
    runningTestDir().reset();
  }
};

TempDir::TempDir(const std::string& tag) {
  const std::string pattern = (std::filesystem::temp_directory_path() / folderName(tag)).string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (::mkdtemp(buffer.data()) == nullptr)
    throw std::runtime_error("TempDir: cannot create " + pattern + ": " + std::strerror(errno));
  path_ = buffer.data();
}

TempDir::~TempDir() { release(::testing::Test::HasFailure()); }

TempDir::TempDir(TempDir&& other) noexcept : path_(std::move(other.path_)) { other.path_.clear(); }

TempDir& TempDir::operator=(TempDir&& other) noexcept {
  if (this != &other) {
    release(::testing::Test::HasFailure());
    path_ = std::move(other.path_);
    other.path_.clear();
  }
  return *this;
}

std::filesystem::path TempDir::subdir(const std::filesystem::path& name) const {
  const std::filesystem::path dir = path_ / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

void TempDir::release(bool keep) {
  if (path_.empty()) return;
  if (keep || keepAll()) {
    std::fprintf(stderr, "TempDir: %s kept: %s\n",
                 keep ? "the test failed, its folder is" : "HUNAV_KEEP_TEMP=1, folder", path_.c_str());
  } else {
    std::error_code ec;  // a destructor must not throw; a folder that cannot go stays
    std::filesystem::remove_all(path_, ec);
  }
  path_.clear();
}

TempDir& testDir() {
  static const bool listening = [] {
    ::testing::UnitTest::GetInstance()->listeners().Append(new TestDirListener);
    return true;
  }();
  (void)listening;
  if (!runningTestDir()) runningTestDir() = std::make_unique<TempDir>();
  return *runningTestDir();
}

}  // namespace hunav::testing
