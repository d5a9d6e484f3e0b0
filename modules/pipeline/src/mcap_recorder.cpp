#include "internal/mcap_recorder.h"

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <cmath>

#include "specht/io/ros_conversion.h"
#include "specht/io/ros_messages.h"

namespace specht::pipeline::internal {
namespace {

using mrpt::poses::CPose3D;
constexpr const char *kMap = "map", *kOdom = "odom", *kBase = "base_link";

io::ros::OccupancyGrid ToRos(const mrpt::maps::COccupancyGridMap2D& g, Stamp t) {
  io::ros::OccupancyGrid m;
  m.header = {t, kMap};
  m.map_load_time = t;
  m.resolution = g.getResolution();
  m.width = g.getSizeX(), m.height = g.getSizeY();
  m.origin.x = g.getXMin(), m.origin.y = g.getYMin();
  m.data.resize(static_cast<size_t>(m.width) * m.height);
  for (uint32_t y = 0; y < m.height; ++y)
    for (uint32_t x = 0; x < m.width; ++x) {
      const float p_free = g.getCell(x, y);  // MRPT keeps p(free)
      m.data[y * m.width + x] =
          std::abs(p_free - 0.5f) < 0.01f ? int8_t{-1} : static_cast<int8_t>(std::lround(100 * (1 - p_free)));
    }
  return m;
}

}  // namespace

McapRecorder::McapRecorder(const std::string& path, double map_every_s, const slam::GridOptions& grid)
    : writer_(path), map_every_s_(map_every_s), grid_options_(grid), grid_(slam::EmptyGrid(grid)) {}

uint16_t McapRecorder::Channel(const std::string& topic, const std::string& type) {
  if (const auto it = channels_.find(topic); it != channels_.end()) return it->second;
  auto schema = schemas_.find(type);
  if (schema == schemas_.end())
    schema = schemas_.emplace(type, writer_.AddSchema(type, "ros2msg", io::ros::Definition(type))).first;
  return channels_[topic] = writer_.AddChannel(schema->second, topic, "cdr");
}

void McapRecorder::Tf(Stamp t, const std::string& parent, const std::string& child, const CPose3D& pose,
                      bool is_static) {
  const io::ros::TransformStamped tf{{t, parent}, child, io::ros::FromMrpt(pose)};
  writer_.Write(Channel(is_static ? "/tf_static" : "/tf", "tf2_msgs/msg/TFMessage"), static_cast<uint64_t>(t.ns),
                io::ros::Encode(std::vector<io::ros::TransformStamped>{tf}));
}

void McapRecorder::Observation(Stamp t, const mrpt::obs::CObservation::Ptr& o) {
  const auto log = static_cast<uint64_t>(t.ns);
  if (const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) {
    const std::string frame = io::ros::FrameName(scan->sensorLabel);
    if (mounted_.insert(frame).second) Tf(t, kBase, frame, scan->sensorPose, true);
    writer_.Write(Channel("/scan", "sensor_msgs/msg/LaserScan"), log,
                  io::ros::Encode(io::ros::FromMrpt(*scan, t, frame)));
  } else if (const auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
    odom_from_base_ = CPose3D(odo->odometry.x(), odo->odometry.y(), 0, odo->odometry.phi(), 0, 0);
    writer_.Write(Channel("/odom", "nav_msgs/msg/Odometry"), log,
                  io::ros::Encode(io::ros::FromMrpt(*odo, t, kOdom, kBase)));
    Tf(t, kOdom, kBase, odom_from_base_);
  }
}

void McapRecorder::Pose(Stamp t, const CPose3D& map_from_base) {
  // map → odom = (map → base) ⊕ (odom → base)⁻¹, with the latest odometry.
  Tf(t, kMap, kOdom, map_from_base + (-odom_from_base_));
}

void McapRecorder::Keyframes(const std::vector<slam::Keyframe>& keyframes, bool moved, Stamp t) {
  stale_ |= moved;
  if (map_every_s_ <= 0 || t.Seconds() - last_map_s_ < map_every_s_) return;
  if (stale_ || inserted_ > keyframes.size()) {
    grid_ = slam::EmptyGrid(grid_options_);
    inserted_ = 0, stale_ = false;
  }
  slam::InsertIntoGrid(keyframes, inserted_, grid_options_, grid_);
  inserted_ = keyframes.size();
  Map(grid_, t);
}

void McapRecorder::Map(const mrpt::maps::COccupancyGridMap2D& grid, Stamp t) {
  writer_.Write(Channel("/map", "nav_msgs/msg/OccupancyGrid"), static_cast<uint64_t>(t.ns),
                io::ros::Encode(ToRos(grid, t)));
  last_map_s_ = t.Seconds();
}

std::map<std::string, uint64_t> McapRecorder::Counts() const {
  std::map<std::string, uint64_t> counts;
  for (const auto& [topic, id] : channels_) {
    const auto it = writer_.channel_messages().find(id);
    counts[topic] = it == writer_.channel_messages().end() ? 0 : it->second;
  }
  return counts;
}

void McapRecorder::Path(const std::string& topic, const std::vector<CPose3D>& poses, Stamp t) {
  io::ros::Path path;
  path.header = {t, kMap};
  for (const auto& p : poses) path.poses.push_back({{t, kMap}, io::ros::FromMrpt(p)});
  writer_.Write(Channel(topic, "nav_msgs/msg/Path"), static_cast<uint64_t>(t.ns), io::ros::Encode(path));
}

void McapRecorder::Poses(const std::string& topic, const std::vector<CPose3D>& poses, Stamp t) {
  io::ros::PoseArray array;
  array.header = {t, kMap};
  for (const auto& p : poses) array.poses.push_back(io::ros::FromMrpt(p));
  writer_.Write(Channel(topic, "geometry_msgs/msg/PoseArray"), static_cast<uint64_t>(t.ns), io::ros::Encode(array));
}

void McapRecorder::Finish(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& trajectory, Stamp end) {
  Map(grid, end);
  io::ros::Path path;
  path.header = {end, kMap};
  for (const auto& p : trajectory) path.poses.push_back({{p.stamp, kMap}, io::ros::FromMrpt(p.pose)});
  writer_.Write(Channel("/trajectory", "nav_msgs/msg/Path"), static_cast<uint64_t>(end.ns), io::ros::Encode(path));
  writer_.Close();
}

}  // namespace specht::pipeline::internal
