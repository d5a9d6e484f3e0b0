// specht/io/carmen.h: CARMEN robot logs (text, one message per line; gzip or plain).
//
//   FLASER n r_1..r_n x y θ odom_x odom_y odom_θ ipc_t host logger_t
//       front laser, first beam at −90°, CARMEN's spacing: 1° for 180/181 beams,
//       0.5° for 360/361 (so 180 beams end at +89°), else 180°/(n−1). x y θ is the
//       laser's pose; the robot sits robot_frontlaser_offset behind it.
//   ROBOTLASER1 type start_angle fov resolution max_range accuracy remission_mode
//       n r_1..r_n m e_1..e_m laser_x laser_y laser_θ robot_x robot_y robot_θ
//       tv rv forward_safety side_safety turn_axis ipc_t host logger_t
//   ODOM x y θ tv rv accel ipc_t host logger_t
//   PARAM name value ...       (robot_frontlaser_offset: laser x offset on the robot)
//   anything else (NEFF, SYNC, TRUEPOS, '#'): ignored
//
// Raw and corrected logs. A raw log (the Freiburg benchmark's .clf files) is the
// recording: a laser message's pose fields are the robot's odometry at that scan,
// ODOM lines are absolute wheel odometry, and there is no reference (score it on a
// published relations file). A corrected log is recognised by its NEFF lines (the
// particle filter that corrected it wrote them); its laser poses are the reference.
//
// Odometry of a raw log: each scan is preceded by an odometry reading at the scan's
// own stamp, taken from its own line (CARMEN's logger wrote the odometry at the scan
// there), so a scan is never paired with an ODOM line stamped after it.
//
// Odometry of a corrected log. Corrected logs (the Freiburg/Radish logs republished with corrected
// poses) re-anchor ODOM to the corrected pose at every laser message, so the raw
// odometry is the chain of ODOM-to-ODOM increments, continuing across each laser
// message from the last ODOM before it:
//   raw_k = raw_{k-1} ⊕ (prev ⊖ odom_k),  prev = odom_k, and at a laser message
//   prev = its pose (the anchor the following ODOM lines are relative to).
// The laser message's pose is never input: it is the reference trajectory.
//
// Time stamps are the ipc time stamps, exactly as logged, per sensor: records are
// delivered in file order (the old logs' stamps come from several hosts and go
// backwards where the file's order, and the odometry, go forwards). A stamp equal to
// the same sensor's previous one (logs without stamps write 0) is moved 1 ms after
// it; a stamp that goes backwards is kept. Notes() says how many of each.
#pragma once

#include <memory>
#include <string>

#include "specht/core/trajectory.h"
#include "specht/io/dataset.h"

namespace specht::io {

bool LooksLikeCarmen(const std::string& path);
// Whether the log holds NEFF lines near its start: a corrected log.
bool IsCorrectedCarmenLog(const std::string& path);
std::unique_ptr<DatasetSource> OpenCarmen(const std::string& path, OnBadRecord on_bad);

// The laser messages' robot poses (base_link in the corrected map frame: a FLASER's
// logged laser pose less the PARAM offset; a ROBOTLASER1's robot pose), stamped like the
// scans OpenCarmen delivers: the reference for `specht eval slam`. Throws InputError
// for a raw log, whose laser poses are odometry.
Trajectory ReadCarmenReference(const std::string& path);

}  // namespace specht::io
