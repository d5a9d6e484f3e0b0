// specht/io/reference.h: reference (ground-truth) trajectories in any format specht
// knows, and where a dataset's own reference is.
#pragma once

#include <string>

#include "specht/core/trajectory.h"

namespace specht::io {

// A CARMEN log (its corrected laser poses), TUM (8 columns) or "t x y theta" (4).
Trajectory ReadReference(const std::string& path);

// A dataset's own reference, or "" when it has none: the corrected poses of a
// corrected CARMEN log (the log itself; a raw log has none), MRPT's `<dataset>.GT.txt` beside a rawlog, or the
// ground_truth.tum that `specht sim` writes beside its sim.rawlog.
std::string DefaultReferencePath(const std::string& dataset, const std::string& format);

}  // namespace specht::io
