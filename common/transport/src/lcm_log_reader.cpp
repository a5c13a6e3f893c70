#include "hunav/lcm_log_reader.hpp"

#include <array>
#include <stdexcept>
#include <system_error>

namespace hunav {

namespace {

constexpr std::uint32_t kSyncWord = 0xEDA1DA01u;
constexpr std::size_t kHeaderBytes = 4 + 8 + 8 + 4 + 4;

std::uint64_t bigEndian(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int k = 0; k < bytes; ++k) v = (v << 8) | p[k];
  return v;
}

}  // namespace

LcmLogReader::LcmLogReader(const std::filesystem::path& file) : file_(file), in_(nullptr, &std::fclose) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw std::runtime_error(file.string() + ": not a regular file (an LCM log was expected)");
  size_ = std::filesystem::file_size(file, ec);
  if (ec) throw std::runtime_error(file.string() + ": " + ec.message());
  in_.reset(std::fopen(file.c_str(), "rb"));
  if (!in_) throw std::runtime_error(file.string() + ": cannot open the file");
}

bool LcmLogReader::fail(const std::string& why) {
  done_ = true;
  stop_reason_ = file_.string() + ": byte " + std::to_string(offset_) + ": " + why;
  return false;
}

const LcmLogReader::Event* LcmLogReader::next() {
  if (done_) return nullptr;
  if (offset_ == size_) {
    done_ = true;
    return nullptr;
  }
  std::array<std::uint8_t, kHeaderBytes> header{};
  if (size_ - offset_ < kHeaderBytes) {
    fail("the file ends inside an event header (" + std::to_string(size_ - offset_) + " bytes left)");
    return nullptr;
  }
  if (std::fread(header.data(), 1, header.size(), in_.get()) != header.size()) {
    fail("read error");
    return nullptr;
  }
  const std::uint8_t* h = header.data();
  if (bigEndian(h, 4) != kSyncWord) {
    fail("no event starts here (not an LCM log, or a corrupt one)");
    return nullptr;
  }
  const auto channel_length = static_cast<std::int32_t>(bigEndian(h + 20, 4));
  const auto data_length = static_cast<std::int32_t>(bigEndian(h + 24, 4));
  const std::uint64_t left = size_ - offset_ - kHeaderBytes;
  if (channel_length <= 0 || channel_length > kMaxChannelLength) {
    fail("channel length " + std::to_string(channel_length) + " (1 to " + std::to_string(kMaxChannelLength) +
         " expected)");
    return nullptr;
  }
  if (data_length < 0 || static_cast<std::uint64_t>(channel_length) + static_cast<std::uint64_t>(data_length) > left) {
    fail("an event of " + std::to_string(channel_length) + " + " + std::to_string(data_length) + " bytes, but only " +
         std::to_string(left) + " are left (a cut or corrupt log)");
    return nullptr;
  }
  event_.number = static_cast<std::int64_t>(bigEndian(h + 4, 8));
  event_.timestamp = static_cast<std::int64_t>(bigEndian(h + 12, 8));
  event_.channel.resize(static_cast<std::size_t>(channel_length));
  event_.data.resize(static_cast<std::size_t>(data_length));
  if (std::fread(event_.channel.data(), 1, event_.channel.size(), in_.get()) != event_.channel.size() ||
      std::fread(event_.data.data(), 1, event_.data.size(), in_.get()) != event_.data.size()) {
    fail("read error");
    return nullptr;
  }
  offset_ += kHeaderBytes + static_cast<std::uint64_t>(channel_length) + static_cast<std::uint64_t>(data_length);
  ++events_read_;
  return &event_;
}

}  // namespace hunav
