// specht/core/statistics.h: summary statistics for reports and benchmarks.
#pragma once

#include <vector>

namespace specht {

// Nearest-rank percentile, q in [0, 1] (element round(q·(n−1)) of the sorted
// values); 0 for no values.
double Percentile(std::vector<double> values, double q);
// 0 for no values.
double Mean(const std::vector<double>& values);

}  // namespace specht
