// Probability columns of the CSV files `specht classify predict` and `specht ais
// eval|predict` write: one column p_<class> per class, four decimals.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace specht::pipeline {

// ",p_<class>" for each class.
inline std::string ProbabilityHeader(const std::vector<std::string>& classes) {
  std::string header;
  for (const auto& c : classes) header += ",p_" + c;
  return header;
}

// Appends ",p" for each of the k probabilities at `p`.
template <class T>
void AppendProbabilities(std::string& csv, const T* p, size_t k) {
  char buf[32];
  for (size_t c = 0; c < k; ++c) {
    std::snprintf(buf, sizeof(buf), ",%.4f", static_cast<double>(p[c]));
    csv += buf;
  }
}

}  // namespace specht::pipeline
