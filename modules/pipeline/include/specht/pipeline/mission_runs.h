// specht/pipeline/mission_runs.h: a scenario's mission driven in closed loop
// (closed_loop.h) once per seed — what `specht run` runs. Per seed: run-<seed>.png
// (the driven path with footprints), map-<seed>/ (SLAM's map, when the drive mapped:
// map_artefact.h, the input of a later run's `map_dir`), steps-<seed>.jsonl (state and pose at the control
// rate) and paths-<seed>.csv (every plan); report.json: each run (success, collisions,
// clearances, parking error, time, planning times, states and transitions) and the
// totals. An interrupt ends after the drive in progress, which is written.
// With `nodes` the stack of each drive runs as `specht node stack` (nodes.h) in a
// process of its own, over DDS; its own folder stack-<seed>/ holds its console and
// report.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "specht/core/params.h"
#include "specht/pipeline/closed_loop.h"

namespace specht::pipeline {

struct MissionRunInputs {
  std::string scenario;                                // scenario file
  std::string mission;                                 // mission file, or "" (park in the scenario's first bay)
  std::optional<std::pair<uint64_t, uint64_t>> seeds;  // first and last; none = the scenario's own
  std::string data_dir;          // detector models and sprites/, for closed_loop.perception camera
  std::string map_dir;           // a mapping drive's map-<seed>/ to localise on (closed_loop.localization map), or ""
  bool nodes = false;            // the stack in a process of its own, over DDS
  bool perception_node = false;  // with nodes: its tracker in a third process
};

// The closed loop's configuration from the parameter sections (car limits over the
// scenario's dimensions, the planners, SLAM, perception), the site map read from
// `map_dir` when one is given; not the camera's.
ClosedLoopConfig LoopConfigFrom(const params::Params& params, const sim::Scenario& scenario,
                                const std::string& map_dir);
// The mission of `mission_file`, or "" for the default (park in the first bay).
std::vector<decide::Goal> MissionOf(const std::string& mission_file, const sim::Scenario& scenario,
                                    const plan::CarOptions& car);

// Exit code 0 when every mission was completed, 1 when one failed, 128 + the signal
// when interrupted.
int RunMissions(const params::Params& params, const MissionRunInputs& in, const std::string& out_dir, bool quiet);

}  // namespace specht::pipeline
