#include "hunav/fingerprint.hpp"

#include <cstdio>

namespace hunav {

std::string Fingerprint::hex() const {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash_));
  return buf;
}

}  // namespace hunav
