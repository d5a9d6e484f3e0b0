// A tuning search (tuning_run.h): searches parameter values that
// minimise (or maximise) a metric of any specht run's JSON report (tune/tune_file.h
// for the file, tune/search.h for the searches). Each evaluation runs in its own
// worker process and directory (DIR/evals/NNNNN) with a timeout; a crash or a
// timeout is logged as failed and the search goes on. Writes
//   evaluations.csv   every evaluation: parameters, metric, seconds, status (the
//                     resume state: --resume continues from it)
//   best.yaml         the best parameters as an overlay: `specht … -p best.yaml`
//   convergence.png   metric per evaluation and best so far, against the defaults
//   report.json/.md   defaults vs best, counts, timing
// Evaluation 0 runs the defaults first: the baseline, and the check that the
// metric is in the report — a misspelled metric stops the tuner there.
#include "specht/pipeline/tuning_run.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>

#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/progress.h"
#include "specht/io/atomic_file.h"
#include "specht/io/data_dir.h"
#include "specht/io/report.h"
#include "specht/tune/plot.h"
#include "specht/tune/runner.h"
#include "specht/tune/tune_file.h"

namespace specht::pipeline {
namespace {

std::string SelfExecutable() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof(buf) - 1);
  if (n <= 0) throw RuntimeError("tune: cannot find this program's path");
  return std::string(buf, static_cast<size_t>(n));
}

std::string Replace(std::string s, const std::map<std::string, std::string>& vars) {
  for (const auto& [from, to] : vars)
    for (size_t p = 0; (p = s.find(from, p)) != std::string::npos; p += to.size()) s.replace(p, from.size(), to);
  return s;
}

// One evaluation: the overlay, then each command in turn, then the metric.
tune::Outcome Evaluate(const tune::TuneFile& t, const std::map<std::string, std::string>& base_vars,
                       const std::string& eval_dir, int repeat, const std::vector<std::string>& values) {
  std::filesystem::create_directories(eval_dir);
  const std::string overlay = eval_dir + "/overlay.yaml";
  io::WriteTextAtomically(overlay, values.empty() ? "{}\n" : t.space.OverlayYaml(values));
  auto vars = base_vars;
  vars["{out}"] = eval_dir, vars["{params}"] = overlay, vars["{repeat}"] = std::to_string(repeat);
  double left_s = t.timeout_s;
  for (const auto& command : t.commands) {
    std::vector<std::string> argv;
    for (const auto& word : command) argv.push_back(Replace(word, vars));
    if (argv[0] == "specht") argv[0] = vars.at("{self}");
    const tune::ProcessResult p = tune::RunProcess(argv, eval_dir + "/log.txt", left_s);
    if (p.interrupted) return {false, 0, "interrupted"};  // not logged (tune/runner.h)
    if (p.timed_out) return {false, 0, "timed out after " + std::to_string(t.timeout_s) + " s"};
    if (p.exit_code != 0)
      return {false, 0,
              "'" + command[0] + (command.size() > 1 ? " " + command[1] : "") + "' exited with " +
                  std::to_string(p.exit_code) + " (see " + eval_dir + "/log.txt)"};
    left_s -= p.seconds;
  }
  return {true, tune::MetricFromReport(eval_dir + "/" + t.report, t.metric), ""};
}

std::string Values(const tune::TuneFile& t, const tune::Evaluation& e) {
  std::string s;
  for (size_t i = 0; i < t.space.size(); ++i)
    s += (s.empty() ? "" : ", ") + t.space.dimensions()[i].key + "=" + (e.values.empty() ? "default" : e.values[i]);
  return s;
}

}  // namespace

int RunTuningSearch(const std::vector<params::ParamInfo>& declared, const TuningInputs& a, const std::string& out_dir,
                    bool quiet) {
  const tune::TuneFile t = tune::LoadTuneFile(a.tune_file, declared);
  if (a.check) {  // the file is valid: say what would be searched
    std::printf("%s: %s search, %d candidates, metric %s (%s)\n", a.tune_file.c_str(), t.search.method.c_str(),
                t.search.budget, t.metric.c_str(), t.maximise ? "maximise" : "minimise");
    for (const auto& d : t.space.dimensions()) {
      std::string range = d.choices.empty() ? "[" + std::to_string(d.min) + ", " + std::to_string(d.max) + "]" +
                                                  (d.log_scale ? " log" : "")
                                            : "{" +
                                                  [&] {
                                                    std::string c;
                                                    for (const auto& x : d.choices) c += (c.empty() ? "" : ", ") + x;
                                                    return c;
                                                  }() +
                                                  "}";
      std::printf("  %-36s %s\n", d.key.c_str(), range.c_str());
    }
    return 0;
  }
  std::map<std::string, std::string> vars = {
      {"{self}", SelfExecutable()}, {"{tune_dir}", std::filesystem::absolute(a.tune_file).parent_path().string()}};
  if (const auto data = io::ResolveDataDir(a.data_dir)) vars["{data}"] = std::filesystem::absolute(*data).string();
  for (const auto& c : t.commands)
    for (const auto& w : c)
      if (w.find("{data}") != std::string::npos && !vars.count("{data}"))
        throw InputError(a.tune_file + ": the commands use {data}: give --data-dir or set SPECHT_DATA_DIR");
  std::filesystem::create_directories(out_dir + "/evals");
  const std::string out = std::filesystem::absolute(out_dir).string();

  tune::RunOptions o;
  o.search = t.search;
  o.maximise = t.maximise;
  o.repeats = t.repeats;
  o.jobs = a.jobs;
  o.log_path = out + "/evaluations.csv";
  o.resume = a.resume;
  ProgressLine progress("tune", "evaluations", !quiet, 10.0);
  o.progress = [&](int done, int planned, const tune::Evaluation& best) {
    char note[96];
    std::snprintf(note, sizeof(note), "best %s %.6g (#%d)", t.metric.c_str(), best.value, best.index);
    progress.Update(done, static_cast<double>(done) / planned, best.ok ? note : "no result yet");
  };
  const tune::RunResult r = tune::RunTuning(t.space, o, [&](int index, int repeat, const std::vector<std::string>& v) {
    char name[32];
    std::snprintf(name, sizeof(name), "/evals/%05d", index);
    return Evaluate(t, vars, out + name + (t.repeats > 1 ? "-r" + std::to_string(repeat) : ""), repeat, v);
  });
  progress.Finish();

  if (InterruptRequested() && r.best < 0) {  // nothing to report but that the log holds no result yet
    io::RunReport report("tune");
    report.SetInterrupted("no finished evaluation");
    report.AddOutput("evaluations.csv");
    report.Write(out);
    return InterruptExitCode();
  }
  const tune::Evaluation& defaults = r.evaluations.at(0);
  if (r.best < 0) throw RuntimeError("tune: no evaluation succeeded (see " + out + "/evaluations.csv)");
  const tune::Evaluation& best = r.evaluations[r.best];
  std::string overlay = "# specht tune " + a.tune_file + ": best of " + std::to_string(r.evaluations.size()) +
                        " evaluations, " + t.metric + " = " + std::to_string(best.value) + " (defaults " +
                        (defaults.ok ? std::to_string(defaults.value) : "failed") + ")\n";
  overlay += best.values.empty() ? "{}\n" : t.space.OverlayYaml(best.values);
  io::WriteTextAtomically(out + "/best.yaml", overlay);
  tune::WriteConvergencePng(r, t.maximise, t.metric, out + "/convergence.png");

  long failed = 0;
  double seconds = 0;
  for (const auto& e : r.evaluations) failed += !e.ok, seconds += e.seconds;
  io::RunReport report("tune");
  auto& j = report.json();
  j["inputs"] = {{"tune_file", a.tune_file},
                 {"metric", t.metric},
                 {"goal", t.maximise ? "maximise" : "minimise"},
                 {"method", t.search.method},
                 {"budget", t.search.budget},
                 {"seed", t.search.seed},
                 {"repeats", t.repeats},
                 {"jobs", a.jobs}};
  j["metrics"] = {{"defaults", defaults.ok ? nlohmann::json(defaults.value) : nlohmann::json()},
                  {"best", best.value},
                  {"best_index", best.index},
                  {"best_parameters", Values(t, best)},
                  {"evaluations", r.evaluations.size()},
                  {"failed", failed},
                  {"reused_from_log", r.reused},
                  {"duplicates_not_run", r.duplicates}};
  j["timing"] = {{"evaluation_seconds_total", seconds}};
  for (const char* f : {"evaluations.csv", "best.yaml", "convergence.png"}) report.AddOutput(f);
  if (InterruptRequested())
    report.SetInterrupted(std::to_string(r.evaluations.size()) + " of " + std::to_string(1 + t.search.budget) +
                          " evaluations (continue with --resume)");
  report.Write(out);
  std::printf(
      "tune: %zu evaluations (%ld failed, %d from the log, %d repeated values not run again); %s: defaults "
      "%s, best %.6g (#%d)\n  %s\n  overlay: %s/best.yaml\n",
      r.evaluations.size(), failed, r.reused, r.duplicates, t.metric.c_str(),
      defaults.ok ? std::to_string(defaults.value).c_str() : "failed", best.value, best.index, Values(t, best).c_str(),
      out.c_str());
  return InterruptExitCode();
}

}  // namespace specht::pipeline
