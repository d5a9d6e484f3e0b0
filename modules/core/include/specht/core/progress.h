// specht/core/progress.h: a progress line for long work, on stderr.
//
// On a terminal the line is redrawn in place at most 5 times a second; otherwise
// (CI logs, pipes) a full line is printed every `log_interval_s` seconds. The line
// shows done/total, percent, rate in units per second and the ETA. Wall time is used
// for display only; it never influences what is computed.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace specht {

// The time left when `fraction` (0, 1] of the work took `elapsed_s`, as "42s",
// "3m07s" or "1h05m"; "?" when the fraction is not positive.
std::string FormatEta(double elapsed_s, double fraction);

// The process's peak resident memory so far (MiB), for reports and benchmarks.
double PeakRssMib();

class ProgressLine {
 public:
  // `unit` names what is counted ("scans"); the rate is shown in unit/s.
  ProgressLine(std::string label, std::string unit, bool enabled = true, double log_interval_s = 10.0);
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;
  ~ProgressLine();

  // `done` units so far; `fraction` of the whole work done in [0, 1] (negative when
  // unknown: no percent or ETA); `note` is appended (e.g. "data 12.3 s").
  void Update(double done, double fraction = -1.0, const std::string& note = "");
  // Prints the closing line: "label: done unit in T s (rate/s) summary".
  void Finish(const std::string& summary = "");

  // The text of the line for given figures (exposed for tests).
  static std::string Format(const std::string& label, double done, double fraction, const std::string& unit,
                            double elapsed_s, const std::string& note);

 private:
  using Clock = std::chrono::steady_clock;
  double ElapsedSeconds() const;

  std::string label_;
  std::string unit_;
  bool enabled_;
  bool tty_;
  double log_interval_s_;
  Clock::time_point start_;
  Clock::time_point last_print_;
  double done_ = 0;
  bool finished_ = false;
};

}  // namespace specht
