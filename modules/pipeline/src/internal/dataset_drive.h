// The loop every dataset replay runs (replay.cpp, nodes.cpp): each observation of a
// source inside the replay window, paced by the replay clock, handed to a consumer,
// with a progress line; it stops at an interrupt (core/interrupt.h), at a corrupt
// record or at a record the consumer cannot use, keeping everything done so far, and
// says which in the report (status, exit code).
#pragma once

#include <mrpt/obs/CObservation.h>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "specht/io/dataset.h"
#include "specht/io/replay.h"
#include "specht/io/report.h"

namespace specht::pipeline::internal {

struct DriveResult {
  std::map<std::string, long> observations;  // by MRPT class name
  std::optional<Stamp> first, last;
  double wall_s = 0;
};

// `add` returns the scans processed so far and a note for the progress line.
using Consumer = std::function<std::pair<long, std::string>(Stamp, const mrpt::obs::CObservation::Ptr&)>;

// Sets `exit_code` to 2 (bad input) or 128 + the signal (interrupted); leaves it otherwise.
DriveResult Drive(io::DatasetSource& source, io::ReplayClock& clock, const Consumer& add, io::StageTimer& timer,
                  io::RunReport& report, bool quiet, int& exit_code);

}  // namespace specht::pipeline::internal
