#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "hunav/lcm_log_reader.hpp"
#include "hunav/testing/temp_dir.hpp"

namespace fs = std::filesystem;
using hunav::LcmLogReader;

namespace {

fs::path scratch(const std::string& name) { return hunav::testing::testDir() / name; }

// Writes events with liblcm's writer (the format lcm-logger writes): channel "CH<k>", k + 1 bytes.
void writeLog(const fs::path& file, int events) {
  lcm::LogFile log(file.string(), "w");
  for (int k = 0; k < events; ++k) {
    std::vector<std::uint8_t> data(static_cast<std::size_t>(k + 1), static_cast<std::uint8_t>(k));
    lcm::LogEvent ev;
    ev.eventnum = k;
    ev.timestamp = 1000 * k;
    ev.channel = "CH" + std::to_string(k);
    ev.datalen = static_cast<std::int32_t>(data.size());
    ev.data = data.data();
    log.writeEvent(&ev);
  }
}

}  // namespace

TEST(LcmLogReader, ReadsWhatLiblcmWrote) {
  const fs::path file = scratch("three.lcmlog");
  writeLog(file, 3);
  LcmLogReader reader(file);
  for (int k = 0; k < 3; ++k) {
    const LcmLogReader::Event* ev = reader.next();
    ASSERT_NE(ev, nullptr) << k;
    EXPECT_EQ(ev->number, k);
    EXPECT_EQ(ev->timestamp, 1000 * k);
    EXPECT_EQ(ev->channel, "CH" + std::to_string(k));
    EXPECT_EQ(ev->data, std::vector<std::uint8_t>(static_cast<std::size_t>(k + 1), static_cast<std::uint8_t>(k)));
  }
  EXPECT_EQ(reader.next(), nullptr);
  EXPECT_TRUE(reader.stopReason().empty()) << reader.stopReason();
  EXPECT_EQ(reader.eventsRead(), 3u);
}

TEST(LcmLogReader, ACutLogEndsAtTheLastWholeEvent) {
  // Event k takes 28 header bytes + 3 channel bytes + k + 1 data bytes: 32 + 33 = 65 for the first
  // two; cutting 2 bytes off the third (34 bytes) leaves it incomplete.
  const fs::path file = scratch("cut.lcmlog");
  writeLog(file, 3);
  ASSERT_EQ(fs::file_size(file), 32u + 33u + 34u);
  fs::resize_file(file, 32 + 33 + 32);
  LcmLogReader reader(file);
  ASSERT_NE(reader.next(), nullptr);
  ASSERT_NE(reader.next(), nullptr);
  EXPECT_EQ(reader.next(), nullptr);
  EXPECT_NE(reader.stopReason().find("byte 65: an event of 3 + 3 bytes, but only 4 are left"), std::string::npos)
      << reader.stopReason();
  // A header cut short is reported too.
  fs::resize_file(file, 32 + 33 + 10);
  LcmLogReader short_header(file);
  short_header.next();
  short_header.next();
  EXPECT_EQ(short_header.next(), nullptr);
  EXPECT_NE(short_header.stopReason().find("ends inside an event header (10 bytes left)"), std::string::npos);
}

TEST(LcmLogReader, AbsurdLengthsAndForeignFilesStopTheReading) {
  const fs::path file = scratch("huge.lcmlog");
  writeLog(file, 2);
  {  // the second event's data length (header bytes 24..27) becomes 0x7fffffff
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(32 + 24);
    const char length[4] = {0x7f, static_cast<char>(0xff), static_cast<char>(0xff), static_cast<char>(0xff)};
    f.write(length, 4);
  }
  LcmLogReader reader(file);
  ASSERT_NE(reader.next(), nullptr);
  EXPECT_EQ(reader.next(), nullptr);
  EXPECT_NE(reader.stopReason().find("byte 32: an event of 3 + 2147483647 bytes"), std::string::npos)
      << reader.stopReason();

  const fs::path text = scratch("text.lcmlog");
  std::ofstream(text) << "not a log, but more than twenty-eight bytes of text\n";
  LcmLogReader foreign(text);
  EXPECT_EQ(foreign.next(), nullptr);
  EXPECT_NE(foreign.stopReason().find("byte 0: no event starts here"), std::string::npos) << foreign.stopReason();

  EXPECT_THROW(LcmLogReader(text.parent_path()), std::runtime_error);  // a folder
  EXPECT_THROW(LcmLogReader(scratch("missing.lcmlog")), std::runtime_error);
}
