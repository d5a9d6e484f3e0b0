// specht/io/trajectory_io.h: trajectories in the formats users have tools for.
//   TUM:        "t x y z qx qy qz qw" per line (seconds, metres, unit quaternion),
//               '#' comments; read by evo and the TUM RGB-D tools.
//   MRPT GT 2D: "t x y theta" per line (MRPT's graphslam-engine ground truth).
//   Relations:  "t1 t2 x y z roll pitch yaw" per line, the Freiburg SLAM benchmark's
//               published relations (Kümmerle et al. 2009): the pose of the scan
//               stamped t2 seen from the scan stamped t1 (metres, radians).
#pragma once

#include <mrpt/poses/CPose2D.h>

#include <cstdint>
#include <string>
#include <vector>

#include "specht/core/trajectory.h"

namespace specht::io {

void WriteTum(const Trajectory& trajectory, const std::string& path);
// Throws InputError naming the file and line on a malformed line.
Trajectory ReadTum(const std::string& path);
Trajectory ReadPose2DText(const std::string& path);

struct ReferenceRelation {
  Stamp t1, t2;
  mrpt::poses::CPose2D delta;  // the scan at t2 in the frame of the scan at t1
  int64_t line = 0;            // in the file, 1-based
};
struct RelationsFile {
  std::string path;
  std::vector<ReferenceRelation> relations;
};
// Throws InputError naming the file and line on a malformed line, and on a file with
// no relation.
RelationsFile ReadRelations(const std::string& path);
// The relations file beside a log, "" when there is none: <dir>/<stem>.relations,
// the stem being the file name less .bz2/.gz and then its extension
// (intel.clf.bz2 → intel.relations).
std::string DefaultRelationsPath(const std::string& dataset);

}  // namespace specht::io
