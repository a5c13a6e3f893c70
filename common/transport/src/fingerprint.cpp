#include "hunav/fingerprint.hpp"

#include <xxhash.h>

#include <cstdio>
#include <hunav/wire_codec.hpp>
#include <stdexcept>

namespace hunav {

void Fingerprint::add(const void* data, std::size_t size) { hash_ = XXH3_64bits_withSeed(data, size, hash_); }

void encodeWorldState(const world_state_t& ws, std::vector<std::uint8_t>& out) {
  out.resize(8 + wire::bodySize(ws));  // the hash, then the fields (wire_codec.hpp, from the .lcm file)
  wire::Writer w(out.data());
  w.i64(world_state_t::getHash());
  wire::writeBody(w, ws);
  if (w.position() != out.data() + out.size()) throw std::logic_error("encodeWorldState: size mismatch");
}

std::string Fingerprint::hex() const {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash_));
  return buf;
}

}  // namespace hunav
