// specht/pipeline/run_directory.h: a run's output directory, created with the run's
// effective parameters in it (params.yaml: defaults, files and overrides merged, so
// `-p params.yaml` repeats the run) before any result is written.
#pragma once

#include <string>

#include "specht/core/params.h"

namespace specht::pipeline {

// Creates `dir` (and its parents) and writes dir/params.yaml atomically.
void PrepareRunDirectory(const std::string& dir, const params::Params& params);

}  // namespace specht::pipeline
