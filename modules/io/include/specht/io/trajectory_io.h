// specht/io/trajectory_io.h: trajectories in the formats users have tools for.
//   TUM:        "t x y z qx qy qz qw" per line (seconds, metres, unit quaternion),
//               '#' comments; read by evo and the TUM RGB-D tools.
//   MRPT GT 2D: "t x y theta" per line (MRPT's graphslam-engine ground truth).
#pragma once

#include <string>

#include "specht/core/trajectory.h"

namespace specht::io {

void WriteTum(const Trajectory& trajectory, const std::string& path);
// Throws InputError naming the file and line on a malformed line.
Trajectory ReadTum(const std::string& path);
Trajectory ReadPose2DText(const std::string& path);

}  // namespace specht::io
