// Files compiled in by hunav_embed_files (cmake/Embed.cmake): the text is the file's, byte for byte,
// also for XML full of quotes, a file in a subfolder and one without a final newline (HuNavSim's
// files); an unknown name throws.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "hunav/embedded_files.hpp"

namespace hunav::testing {
extern const EmbeddedFiles kEmbeddedTestFiles;  // tests/common/CMakeLists.txt
}

namespace {
std::string fileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}
}  // namespace

TEST(EmbeddedFiles, TheTextIsTheFilesByteForByte) {
  const hunav::EmbeddedFiles& files = hunav::testing::kEmbeddedTestFiles;
  int count = 0;
  for (const hunav::EmbeddedFile& f : files) {
    const std::string on_disk =
        fileText(std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/" + std::string(f.name));
    ASSERT_FALSE(on_disk.empty()) << f.name;
    EXPECT_EQ(std::string(f.text), on_disk) << f.name;
    ++count;
  }
  EXPECT_EQ(count, 3);
  EXPECT_EQ(files.text("agents.yaml"), fileText(std::string(HUNAV_SOURCE_DIR) + "/tests/data/hunav_files/agents.yaml"));
  EXPECT_THROW(files.text("no_such_file.yaml"), std::out_of_range);
}
