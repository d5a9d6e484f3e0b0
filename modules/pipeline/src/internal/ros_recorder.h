// A replay as ROS 2 messages — recorded as MCAP (io/mcap.h) for Foxglove and for
// playback into a ROS 2 system, published on DDS topics (net/topics.h) for ROS 2
// nodes, or both: the same messages, the same CDR bytes (io/ros_messages.h):
//   /scan        sensor_msgs/msg/LaserScan, each scan as read (frame: its label)
//   /odom        nav_msgs/msg/Odometry, each odometry reading (odom → base_link)
//   /imu         sensor_msgs/msg/Imu, each IMU reading (base_link)
//   /tf          tf2_msgs/msg/TFMessage: odom → base_link at each odometry reading,
//                map → odom at each scan SLAM placed (REP-105)
//   /tf_static   base_link → each scan frame (its mount): every mount known so far in
//                one message, as ROS 2's static broadcaster sends them (a latched
//                topic keeps its last message only)
//   /map         nav_msgs/msg/OccupancyGrid every map_every_s of data and at the end
//   /trajectory  nav_msgs/msg/Path, the estimate at the end
// The closed loop adds /path (the path the car follows) and /tracks (the tracks'
// poses, geometry_msgs/msg/PoseArray), and its map is the world model's static layer.
// Messages are logged at their stamps. Replaying the file (`specht slam run.mcap`)
// reads the scans and odometry back. Each message is an input echoed (the scans,
// odometry and their TF) or an estimate (the rest): a player publishes the inputs, a
// SLAM node the estimates.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "specht/core/trajectory.h"
#include "specht/io/ros_messages.h"
#include "specht/net/topics.h"
#include "specht/slam/scan_matching.h"

namespace specht::pipeline::internal {

enum class Origin { kInput, kEstimate };

// Where a recorder's messages go.
class MessageSink {
 public:
  virtual ~MessageSink() = default;
  virtual void Write(const std::string& topic, const std::string& type, Origin origin, Stamp t,
                     const std::vector<uint8_t>& cdr) = 0;
  virtual void Close() {}
};

// An MCAP file with ROS 2 schemas (every message).
std::unique_ptr<MessageSink> McapSink(const std::string& path);
// Where `--mcap FILE` goes: a bare file name into the output folder, a path as given.
std::string RecordingPath(const std::string& out_dir, const std::string& file);
// DDS topics (the messages of `origin` only).
std::unique_ptr<MessageSink> DdsSink(std::shared_ptr<net::TopicPublisher> publisher, Origin origin);

class RosRecorder {
 public:
  RosRecorder(std::vector<std::unique_ptr<MessageSink>> sinks, double map_every_s, const slam::GridOptions& grid);
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
  // The final map, the trajectory; closes the sinks.
  void Finish(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& trajectory, Stamp end);
  // Messages written, by topic (for the report).
  std::map<std::string, uint64_t> Counts() const;

 private:
  void Emit(const std::string& topic, const std::string& type, Origin origin, Stamp t, const std::vector<uint8_t>& cdr);
  void Tf(Stamp t, const std::string& parent, const std::string& child, const mrpt::poses::CPose3D& pose,
          Origin origin);
  std::vector<std::unique_ptr<MessageSink>> sinks_;
  std::map<std::string, uint64_t> counts_;
  double map_every_s_;
  slam::GridOptions grid_options_;
  std::vector<io::ros::TransformStamped> mounts_;  // on /tf_static
  std::set<std::string> mounted_;                  // their frames
  mrpt::poses::CPose3D odom_from_base_;            // the latest odometry reading
  mrpt::maps::COccupancyGridMap2D grid_;
  size_t inserted_ = 0;
  bool stale_ = false;
  double last_map_s_ = -1e18;
};

}  // namespace specht::pipeline::internal
