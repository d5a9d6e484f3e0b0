// A replay recorded as MCAP (io/mcap.h) with ROS 2 schemas, for Foxglove and for
// playback into a ROS 2 system:
//   /scan        sensor_msgs/msg/LaserScan, each scan as read (frame: its label)
//   /odom        nav_msgs/msg/Odometry, each odometry reading (odom → base_link)
//   /tf          tf2_msgs/msg/TFMessage: odom → base_link at each odometry reading,
//                map → odom at each scan SLAM placed (REP-105)
//   /tf_static   base_link → each scan frame (its mount)
//   /map         nav_msgs/msg/OccupancyGrid every map_every_s of data and at the end
//   /trajectory  nav_msgs/msg/Path, the estimate at the end
// The closed loop adds /path (the path the car follows) and /tracks (the tracks'
// poses, geometry_msgs/msg/PoseArray), and its map is the world model's static layer.
// Messages are logged at their stamps. Replaying the file (`specht slam run.mcap`)
// reads the scans and odometry back.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <set>
#include <string>
#include <vector>

#include "specht/core/trajectory.h"
#include "specht/io/mcap.h"
#include "specht/slam/scan_matching.h"

namespace specht::pipeline::internal {

class McapRecorder {
 public:
  McapRecorder(const std::string& path, double map_every_s, const slam::GridOptions& grid);
  // Every observation of the replay, in order.
  void Observation(Stamp t, const mrpt::obs::CObservation::Ptr& o);
  // The pose SLAM (or the localizer) gave the scan of stamp `t` (map frame).
  void Pose(Stamp t, const mrpt::poses::CPose3D& map_from_base);
  // At every scan placed: /map when one is due, drawn from the keyframes added since
  // the last (`moved`: a loop closure moved their poses: drawn again from all).
  void Keyframes(const std::vector<slam::Keyframe>& keyframes, bool moved, Stamp t);
  // A map that is not drawn from keyframes here (the closed loop's static layer).
  void Map(const mrpt::maps::COccupancyGridMap2D& grid, Stamp t);
  // A path (map frame) on `topic` as nav_msgs/Path; poses as geometry_msgs/PoseArray.
  void Path(const std::string& topic, const std::vector<mrpt::poses::CPose3D>& poses, Stamp t);
  void Poses(const std::string& topic, const std::vector<mrpt::poses::CPose3D>& poses, Stamp t);
  // The final map, the trajectory; closes the file.
  void Finish(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& trajectory, Stamp end);
  // Messages written, by topic (for the report).
  std::map<std::string, uint64_t> Counts() const;

 private:
  uint16_t Channel(const std::string& topic, const std::string& type);
  void Tf(Stamp t, const std::string& parent, const std::string& child, const mrpt::poses::CPose3D& pose,
          bool is_static = false);
  io::McapWriter writer_;
  double map_every_s_;
  slam::GridOptions grid_options_;
  std::map<std::string, uint16_t> schemas_, channels_;
  std::set<std::string> mounted_;        // scan frames on /tf_static
  mrpt::poses::CPose3D odom_from_base_;  // the latest odometry reading
  mrpt::maps::COccupancyGridMap2D grid_;
  size_t inserted_ = 0;
  bool stale_ = false;
  double last_map_s_ = -1e18;
};

}  // namespace specht::pipeline::internal
