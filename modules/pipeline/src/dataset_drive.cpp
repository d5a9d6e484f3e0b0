#include "internal/dataset_drive.h"

#include <chrono>
#include <tuple>

#include "specht/core/interrupt.h"
#include "specht/core/log.h"
#include "specht/core/progress.h"

namespace specht::pipeline::internal {

DriveResult Drive(io::DatasetSource& source, io::ReplayClock& clock, const Consumer& add, io::StageTimer& timer,
                  io::RunReport& report, bool quiet, int& exit_code) {
  DriveResult r;
  ProgressLine progress(report.json().value("command", "run"), "scans", !quiet);
  const auto wall0 = std::chrono::steady_clock::now();
  long scans = 0;
  while (true) {
    if (InterruptRequested()) {  // stop at this record boundary, keep everything so far
      spdlog::warn("{}: stopping after {} scans", InterruptName(), scans);
      report.SetInterrupted(std::to_string(scans) + " scans");
      exit_code = InterruptExitCode();
      break;
    }
    std::optional<io::Observation> obs;
    try {
      auto t = timer.Time("read");
      obs = source.Next();
    } catch (const io::DatasetError& e) {
      // Stop here and keep everything computed so far.
      spdlog::error("{}", e.what());
      report.SetIncomplete(e.what());
      exit_code = 2;
      break;
    }
    if (!obs && InterruptRequested()) continue;  // a live source ends on the signal: interrupted, not complete
    if (!obs) break;
    const auto verdict = clock.Classify(obs->stamp);
    if (verdict == io::ReplayClock::Verdict::kBefore) continue;
    if (verdict == io::ReplayClock::Verdict::kAfter) break;
    clock.WaitFor(obs->stamp);
    ++r.observations[obs->data->GetRuntimeClass()->className];
    std::string note;
    try {
      std::tie(scans, note) = add(obs->stamp, obs->data);
    } catch (const InputError& e) {
      // A record the stack cannot use (e.g. a stereo pair without calibration): stop
      // here as at a corrupt record, keeping everything computed so far.
      spdlog::error("{}: {}", source.Path(), e.what());
      report.SetIncomplete(e.what());
      exit_code = 2;
      break;
    }
    if (!r.first) r.first = obs->stamp;
    r.last = obs->stamp;
    progress.Update(static_cast<double>(scans), source.FractionRead(), note);
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  progress.Finish();
  return r;
}

}  // namespace specht::pipeline::internal
