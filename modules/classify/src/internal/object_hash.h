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

// ObjectHash with its bits mixed (splitmix64's finaliser): FNV-1a's order of short
// ids that differ in a digit barely changes with the seed ("o20"…"o39" sort first
// for seeds 1 and 2 alike), so an order that must change with the seed uses this.
inline uint64_t MixedObjectHash(const std::string& id, int seed) {
  uint64_t z = ObjectHash(id, seed) + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace specht::classify::internal
