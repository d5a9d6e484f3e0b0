// specht/tune/runner.h: the tuning loop — generations from a search (search.h),
// candidates decoded by the space (space.h), evaluated in parallel by a caller's
// function (in `specht tune`: a worker process per evaluation), every finished
// evaluation appended to a CSV log at once. The log is also the resume state:
// with `resume`, the loop replays the search and takes each candidate's result
// from the log instead of evaluating it again, so an interrupted search continues
// exactly where it was (same seed → same final result). A candidate whose decoded
// values an earlier candidate already had (a GA's elite asked again, two children
// alike on a coarse grid) takes that outcome instead of running again: evaluations
// are deterministic, so a second run would only cost time.
//
// Evaluation 0 is the defaults (no overlay): the baseline every result is compared
// with, and the first check that the metric exists — an Evaluator may throw
// InputError there (e.g. the metric is not in the report) to stop before the search.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "specht/tune/search.h"
#include "specht/tune/space.h"

namespace specht::tune {

struct Outcome {
  bool ok = false;
  double value = std::numeric_limits<double>::quiet_NaN();  // the metric as reported
  std::string error;                                        // why not ok
};

// Evaluates candidate `index` (0 = defaults: `values` empty), repetition `repeat`.
// Called from several threads at once when jobs > 1.
using Evaluator = std::function<Outcome(int index, int repeat, const std::vector<std::string>& values)>;

struct Evaluation {
  int index = 0, generation = 0;  // generation 0 = the defaults
  std::vector<std::string> values;
  bool ok = false;
  double value = std::numeric_limits<double>::quiet_NaN();  // mean over repeats
  double seconds = 0;
  std::string error;
};

struct RunOptions {
  SearchOptions search;
  bool maximise = false;
  int repeats = 1;
  int jobs = 1;
  std::string log_path;  // CSV; required
  bool resume = false;   // take results from an existing log
  // After each evaluation: evaluations done (incl. the defaults), planned, best so far.
  std::function<void(int done, int planned, const Evaluation& best)> progress;
  // Stop (as if killed) after this many new evaluations; 0 = never. For tests of resume.
  int stop_after = 0;
};

struct RunResult {
  std::vector<Evaluation> evaluations;  // by index
  int best = -1;                        // index of the best ok evaluation (−1: none)
  bool complete = false;                // false when stopped by stop_after or an interrupt
  int reused = 0;                       // results taken from the log
  int duplicates = 0;                   // candidates whose values an earlier one had: its outcome, not run
};

// Throws InputError on a log of another search (other keys or candidates), or what
// the evaluator throws for the defaults.
RunResult RunTuning(const SearchSpace& space, const RunOptions& options, const Evaluator& evaluate);

}  // namespace specht::tune
