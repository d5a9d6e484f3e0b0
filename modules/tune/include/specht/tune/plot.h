// specht/tune/plot.h: the convergence plot of a tuning run — every evaluation's
// metric (grey dots; failed ones as red ticks at the bottom), the best so far (blue
// line) and the defaults (dashed), against the evaluation index.
#pragma once

#include <string>
#include <vector>

#include "specht/tune/runner.h"

namespace specht::tune {

void WriteConvergencePng(const RunResult& result, bool maximise, const std::string& metric, const std::string& path);

}  // namespace specht::tune
