#include "hunav/fingerprint.hpp"

#include <xxhash.h>

#include <cstdio>

namespace hunav {

void Fingerprint::add(const void* data, std::size_t size) { hash_ = XXH3_64bits_withSeed(data, size, hash_); }

std::string Fingerprint::hex() const {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash_));
  return buf;
}

}  // namespace hunav
