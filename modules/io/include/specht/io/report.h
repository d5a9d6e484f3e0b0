// specht/io/report.h: the run report every app writes next to its outputs:
// report.json (machine-readable: inputs, parameters file, counts, per-stage timing,
// real-time factor, metrics, status) and report.md (the same for people).
//
// JSON layout (keys are stable; the tuner reads metrics from it):
//   { "command", "status": "complete"|"incomplete"|"interrupted"|"failed", "error",
//     "inputs": {...}, "counts": {...}, "timing": {"stages": {name: {"total_ms",
//     "calls", "ms_per_call"}}, "wall_s", "data_s", "real_time_factor"},
//     "metrics": {...}, "outputs": [file, ...] }
#pragma once

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace specht::io {

// Accumulates wall time per named stage.
class StageTimer {
 public:
  class Scope {
   public:
    Scope(StageTimer& timer, std::string stage);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    StageTimer& timer_;
    std::string stage_;
    std::chrono::steady_clock::time_point start_;
  };
  Scope Time(const std::string& stage) { return Scope(*this, stage); }
  void Add(const std::string& stage, double ms);
  double TotalMs(const std::string& stage) const;
  nlohmann::json ToJson() const;

 private:
  struct Entry {
    double total_ms = 0;
    long calls = 0;
  };
  std::map<std::string, Entry> stages_;
};

// How a report gives a spread of values (wall-clock milliseconds, say): {"count",
// "p50", "p99", …, "max"}, a nearest-rank percentile (core/statistics.h) for each of
// `levels`; zeros for no values.
nlohmann::json Quantiles(const std::vector<double>& values, std::initializer_list<double> levels);

class RunReport {
 public:
  explicit RunReport(std::string command);
  nlohmann::json& json() { return json_; }
  // The input broke off (a corrupt record): what was computed before it is reported.
  void SetIncomplete(const std::string& error);
  // A signal stopped the run (core/interrupt.h) after `done` (e.g. "5210 scans").
  void SetInterrupted(const std::string& done);
  // How a run that a signal may have stopped (after `done`), or that stopped early for
  // the reason `stopped` (non-empty; logged as an error), ended: sets the status and
  // returns the exit code — 128 + the signal, 1, or 0 when it ran to its end.
  int Ended(const std::string& done, const std::string& stopped);
  void AddOutput(const std::string& file);
  // Writes report.json and report.md into `dir` (atomically).
  void Write(const std::string& dir) const;
  static std::string ToMarkdown(const nlohmann::json& report);

 private:
  nlohmann::json json_;
};

}  // namespace specht::io
