// net/src/internal/address.h: what the DDS settings and launch files both check.
#pragma once

#include <arpa/inet.h>

#include <string>

namespace specht::net::internal {

// True when `address` is a dotted IPv4 address, the form Cyclone's interface and peer
// settings take here.
inline bool IsIpv4(const std::string& address) {
  in_addr parsed{};
  return inet_pton(AF_INET, address.c_str(), &parsed) == 1;
}

}  // namespace specht::net::internal
