// The candidate nearest to `key` by edit distance, for "did you mean" hints; empty
// when none is within `max_distance` edits.
#pragma once

#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::tune::internal {

inline std::string Nearest(const std::vector<std::string>& candidates, const std::string& key,
                           size_t max_distance = 4) {
  std::string best;
  size_t best_distance = max_distance + 1;
  for (const auto& c : candidates)
    if (const size_t d = params::EditDistance(c, key); d < best_distance) best_distance = d, best = c;
  return best;
}

}  // namespace specht::tune::internal
