// specht/pipeline/tuning_run.h: a parameter search — what `specht tune` runs. It
// minimises (or maximises) a metric of any specht run's JSON report (tune/tune_file.h
// for the file, tune/search.h for the searches); each evaluation runs in its own worker
// process and directory (<out>/evals/NNNNN) with a timeout, and a crash or a timeout
// is logged as failed while the search goes on. Writes evaluations.csv (every
// evaluation: the resume state), best.yaml (the best parameters as an overlay),
// convergence.png and a report (defaults against best, counts, timing). Evaluation 0
// runs the defaults: the baseline, and the check that the metric is in the report.
#pragma once

#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::pipeline {

struct TuningInputs {
  std::string tune_file;
  std::string data_dir;  // for {data} in the commands ("" = $SPECHT_DATA_DIR)
  int jobs = 1;          // evaluations in parallel
  bool resume = false;   // continue from <out>/evaluations.csv
  bool check = false;    // only check the tune file and print the search space
};

// `declared` is every parameter the commands know (the search space is checked
// against it before anything runs). Returns 0, or 128 + the signal when interrupted
// (the log stays resumable).
int RunTuningSearch(const std::vector<params::ParamInfo>& declared, const TuningInputs& in, const std::string& out_dir,
                    bool quiet);

}  // namespace specht::pipeline
