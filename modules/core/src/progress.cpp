#include "specht/core/progress.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <iomanip>
#include <sstream>

namespace specht {
namespace {

std::string FormatDuration(double s) {
  if (!std::isfinite(s) || s < 0) return "?";
  const int total = static_cast<int>(std::lround(s));
  std::ostringstream out;
  if (total >= 3600)
    out << total / 3600 << "h" << std::setw(2) << std::setfill('0') << (total % 3600) / 60 << "m";
  else if (total >= 60)
    out << total / 60 << "m" << std::setw(2) << std::setfill('0') << total % 60 << "s";
  else
    out << total << "s";
  return out.str();
}

}  // namespace

std::string FormatEta(double elapsed_s, double fraction) {
  return fraction > 0 ? FormatDuration(elapsed_s * (1.0 - fraction) / fraction) : "?";
}

ProgressLine::ProgressLine(std::string label, std::string unit, bool enabled, double log_interval_s)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      enabled_(enabled),
      tty_(isatty(STDERR_FILENO) != 0),
      log_interval_s_(log_interval_s),
      start_(Clock::now()),
      last_print_(start_) {}

ProgressLine::~ProgressLine() {
  if (enabled_ && tty_ && !finished_ && done_ > 0) std::fputs("\n", stderr);
}

double ProgressLine::ElapsedSeconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

std::string ProgressLine::Format(const std::string& label, double done, double fraction, const std::string& unit,
                                 double elapsed_s, const std::string& note) {
  std::ostringstream out;
  out << label << ": ";
  if (fraction >= 0) out << std::fixed << std::setprecision(1) << 100.0 * fraction << "% ";
  out << static_cast<long long>(done) << " " << unit;
  const double rate = elapsed_s > 0 ? done / elapsed_s : 0.0;
  out << std::fixed << std::setprecision(1) << " " << rate << " " << unit << "/s";
  if (fraction >= 0) out << " ETA " << FormatEta(elapsed_s, fraction);
  if (!note.empty()) out << " " << note;
  return out.str();
}

void ProgressLine::Update(double done, double fraction, const std::string& note) {
  done_ = done;
  if (!enabled_) return;
  const auto now = Clock::now();
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (since < (tty_ ? 0.2 : log_interval_s_)) return;
  last_print_ = now;
  const std::string line = Format(label_, done, fraction, unit_, ElapsedSeconds(), note);
  if (tty_)
    std::fprintf(stderr, "\r\033[K%s", line.c_str());
  else
    std::fprintf(stderr, "%s\n", line.c_str());
  std::fflush(stderr);
}

void ProgressLine::Finish(const std::string& summary) {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  const double elapsed = ElapsedSeconds();
  std::ostringstream out;
  out << label_ << ": " << static_cast<long long>(done_) << " " << unit_ << " in " << std::fixed << std::setprecision(2)
      << elapsed << " s (" << std::setprecision(1) << (elapsed > 0 ? done_ / elapsed : 0.0) << " " << unit_ << "/s)";
  if (!summary.empty()) out << " " << summary;
  if (tty_)
    std::fprintf(stderr, "\r\033[K%s\n", out.str().c_str());
  else
    std::fprintf(stderr, "%s\n", out.str().c_str());
  std::fflush(stderr);
}

double PeakRssMib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace specht
