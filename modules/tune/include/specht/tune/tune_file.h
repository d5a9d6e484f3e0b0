// specht/tune/tune_file.h: what `specht tune` reads.
//
//   run:                        # one or more command lines, run in order per
//     - specht stereo L.png R.png -p {params} -o {out}/stereo -q     # evaluation
//     - specht eval stereo --estimate {out}/stereo/disparity.png --truth GT.png -o {out}/eval
//   report: eval/report.json    # the JSON report to read, relative to {out}
//   metric: metrics.d1_all      # dotted path of a number in it
//   goal: minimise              # or maximise
//   repeats: 1                  # evaluations per candidate, averaged ({repeat} = 0, 1, …)
//   timeout_s: 120              # per evaluation (all its commands); then it is failed
//   parameters: {...}           # see space.h
//   search: {method: ga, budget: 100, population: 10, seed: 1}   # see search.h
//
// Placeholders in commands: {out} the evaluation's own directory, {params} its
// parameter overlay (YAML), {data} the data directory, {repeat} the repetition,
// {tune_dir} the tune file's directory. A command's first word `specht` is this
// program. Words are split at spaces (no quoting).
#pragma once

#include <string>
#include <vector>

#include "specht/tune/search.h"
#include "specht/tune/space.h"

namespace specht::tune {

struct TuneFile {
  std::string path;
  std::vector<std::vector<std::string>> commands;  // words, placeholders unexpanded
  std::string report = "report.json";
  std::string metric;
  bool maximise = false;
  int repeats = 1;
  double timeout_s = 600;
  SearchOptions search;
  SearchSpace space{{}};
};

// Throws InputError naming the file, line and field: unknown fields, a missing
// run/metric/parameters, a bad goal, and everything SearchSpace rejects.
TuneFile LoadTuneFile(const std::string& path, const std::vector<params::ParamInfo>& declared);

// The number at a dotted path of a JSON document; throws InputError naming the
// report, the path and the nearest numeric paths it does have.
double MetricFromReport(const std::string& report_path, const std::string& metric);

// Runs `argv` (argv[0] a path, or a name looked up in PATH) in its own process group with stdout and stderr
// appended to `log_path`; kills the group after `timeout_s`. On an interrupt of this
// process (core/interrupt.h) the group gets SIGTERM (SIGKILL 5 s later): the worker
// stops with its parent.
struct ProcessResult {
  int exit_code = -1;
  bool timed_out = false;
  bool interrupted = false;
  double seconds = 0;
};
ProcessResult RunProcess(const std::vector<std::string>& argv, const std::string& log_path, double timeout_s);

}  // namespace specht::tune
