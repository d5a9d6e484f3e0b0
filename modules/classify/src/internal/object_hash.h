// Seeded FNV-1a hash of an object id: stable across runs and platforms (std::hash
// is not), so splits and folds by object are reproducible everywhere.
#pragma once

#include <cstdint>
#include <string>

namespace specht::classify::internal {

inline uint64_t ObjectHash(const std::string& id, int seed) {
  uint64_t h = 1469598103934665603ULL ^ static_cast<uint64_t>(seed);
  for (unsigned char c : id) h = (h ^ c) * 1099511628211ULL;
  return h;
}

}  // namespace specht::classify::internal
