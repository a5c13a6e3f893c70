#pragma once
// FNV-1a 64 over a byte stream: the run fingerprint is this hash of every encoded world state.
#include <cstddef>
#include <cstdint>
#include <string>

namespace hunav {

class Fingerprint {
 public:
  void add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    std::uint64_t h = hash_;  // a local: the compiler keeps it in a register
    for (std::size_t i = 0; i < size; ++i) {
      h ^= bytes[i];
      h *= 0x100000001b3ULL;
    }
    hash_ = h;
  }
  std::uint64_t value() const { return hash_; }
  std::string hex() const;

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

}  // namespace hunav
