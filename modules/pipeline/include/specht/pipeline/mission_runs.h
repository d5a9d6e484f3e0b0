// specht/pipeline/mission_runs.h: a scenario's mission driven in closed loop
// (closed_loop.h) once per seed — what `specht run` runs. Per seed: run-<seed>.png
// (the driven path with footprints), map-<seed>/ (SLAM's map, when the drive mapped:
// map_artefact.h, the input of a later run's `map_dir`), steps-<seed>.jsonl (state and pose at the control
// rate) and paths-<seed>.csv (every plan); report.json: each run (success, collisions,
// clearances, parking error, time, planning times, states and transitions) and the
// totals. An interrupt ends after the drive in progress, which is written.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "specht/core/params.h"

namespace specht::pipeline {

struct MissionRunInputs {
  std::string scenario;                                // scenario file
  std::string mission;                                 // mission file, or "" (park in the scenario's first bay)
  std::optional<std::pair<uint64_t, uint64_t>> seeds;  // first and last; none = the scenario's own
  std::string data_dir;  // detector models and sprites/, for closed_loop.perception camera
  std::string map_dir;   // a mapping drive's map-<seed>/ to localise on (closed_loop.localization map), or ""
};

// Exit code 0 when every mission was completed, 1 when one failed, 128 + the signal
// when interrupted.
int RunMissions(const params::Params& params, const MissionRunInputs& in, const std::string& out_dir, bool quiet);

}  // namespace specht::pipeline
