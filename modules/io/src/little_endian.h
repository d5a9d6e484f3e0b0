// The unsigned integer stored in `n` bytes (at most 8), least significant first: the
// length and version fields of MRPT's rawlog archives and ROS 1 bags.
#pragma once

#include <cstddef>
#include <cstdint>

namespace specht::io {

inline uint64_t LittleEndian(const unsigned char* bytes, size_t n) {
  uint64_t value = 0;
  for (size_t i = n; i-- > 0;) value = value << 8 | bytes[i];
  return value;
}

}  // namespace specht::io
