#pragma once
// The run fingerprint: a 64-bit hash of every encoded world state, chained message by message with
// XXH3 (libxxhash): h_0 = 0, h_k = XXH3_64bits_withSeed(bytes of message k, its size, h_{k-1}).
// XXH3 reads 8-byte words in wide vector lanes (~40 us for the world state of 1000 people, where
// the byte-wise FNV-1a used before took ~0.25 ms), and the chain keeps the order of messages.
#include <cstddef>
#include <cstdint>
#include <string>

namespace hunav {

class Fingerprint {
 public:
  // Adds one message (its whole encoding).
  void add(const void* data, std::size_t size);
  std::uint64_t value() const { return hash_; }
  std::string hex() const;

 private:
  std::uint64_t hash_ = 0;
};

}  // namespace hunav
