#pragma once
// The run fingerprint: a 64-bit hash of every encoded world state, chained message by message with
// XXH3 (libxxhash): h_0 = 0, h_k = XXH3_64bits_withSeed(bytes of message k, its size, h_{k-1}).
// The chain keeps the order of messages; XXH3 is fast enough to hash a crowd's state every tick
// (docs/world.md, "The run fingerprint", measures it).
#include <cstddef>
#include <cstdint>
#include <hunav/world_state_t.hpp>
#include <string>
#include <vector>

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

// The LCM encoding of a world state, byte for byte what world_state_t::encode() writes (fingerprint
// hash, then every field big-endian in declaration order), written inline by the codec generated
// from the .lcm files (wire_codec.hpp) instead of lcm-gen's call per field: the world encodes the
// whole crowd every tick (for the fingerprint and the LCM publish), where those calls cost far more
// than the bytes (docs/performance.md, "Crowds").
// Replaces `out` (its storage is reused). As the generated encoder, it writes num_goals /
// num_obstacles / num_agents / num_collisions elements; the counts must not exceed the arrays. A
// string holding a NUL throws std::runtime_error, as Bus::encode does for it (LCM would size and
// write it differently).
void encodeWorldState(const world_state_t& ws, std::vector<std::uint8_t>& out);

}  // namespace hunav
