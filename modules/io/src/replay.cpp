#include "specht/io/replay.h"

#include <thread>

namespace specht::io {

std::vector<std::string> ReplayOptions::Relations() const {
  if (to_s > 0 && to_s <= from_s)
    return {"to_s (" + std::to_string(to_s) + ") must be after from_s (" + std::to_string(from_s) + ")"};
  return {};
}

ReplayClock::Verdict ReplayClock::Classify(Stamp stamp) {
  if (!first_) first_ = stamp;
  const double t = SecondsBetween(*first_, stamp);
  // Only a window that starts later drops records: a stamp before the first one (a
  // sensor whose stamps go backwards) is still inside a window from the start.
  if (options_.from_s > 0 && t < options_.from_s) return Verdict::kBefore;
  if (options_.to_s > 0 && t > options_.to_s) return Verdict::kAfter;
  return Verdict::kInside;
}

void ReplayClock::WaitFor(Stamp stamp) {
  if (options_.rate <= 0) return;
  if (!pace_origin_) {
    pace_origin_ = stamp;
    wall_origin_ = std::chrono::steady_clock::now();
    return;
  }
  const double due_s = SecondsBetween(*pace_origin_, stamp) / options_.rate;
  if (due_s <= 0) return;
  std::this_thread::sleep_until(wall_origin_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                   std::chrono::duration<double>(due_s)));
}

}  // namespace specht::io
