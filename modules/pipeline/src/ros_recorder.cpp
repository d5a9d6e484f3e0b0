#include "internal/ros_recorder.h"

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <cmath>

#include "specht/io/mcap.h"
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

class Mcap : public MessageSink {
 public:
  explicit Mcap(const std::string& path) : writer_(path) {}
  void Write(const std::string& topic, const std::string& type, Origin, Stamp t,
             const std::vector<uint8_t>& cdr) override {
    writer_.Write(Channel(topic, type), static_cast<uint64_t>(t.ns), cdr);
  }
  void Close() override { writer_.Close(); }

 private:
  uint16_t Channel(const std::string& topic, const std::string& type) {
    if (const auto it = channels_.find(topic); it != channels_.end()) return it->second;
    auto schema = schemas_.find(type);
    if (schema == schemas_.end())
      schema = schemas_.emplace(type, writer_.AddSchema(type, "ros2msg", io::ros::Definition(type))).first;
    return channels_[topic] = writer_.AddChannel(schema->second, topic, "cdr");
  }
  io::McapWriter writer_;
  std::map<std::string, uint16_t> schemas_, channels_;
};

class PublishingSink : public MessageSink {
 public:
  PublishingSink(std::shared_ptr<net::TopicPublisher> publisher, Origin origin)
      : publisher_(std::move(publisher)), origin_(origin) {}
  void Write(const std::string& topic, const std::string& type, Origin origin, Stamp t,
             const std::vector<uint8_t>& cdr) override {
    if (origin == origin_) publisher_->Publish(topic, type, t, cdr);
  }

 private:
  std::shared_ptr<net::TopicPublisher> publisher_;
  Origin origin_;
};

}  // namespace

std::unique_ptr<MessageSink> McapSink(const std::string& path) { return std::make_unique<Mcap>(path); }

std::string RecordingPath(const std::string& out_dir, const std::string& file) {
  return file.find('/') == std::string::npos ? out_dir + "/" + file : file;
}

std::unique_ptr<MessageSink> DdsSink(std::shared_ptr<net::TopicPublisher> publisher, Origin origin) {
  return std::make_unique<PublishingSink>(std::move(publisher), origin);
}

RosRecorder::RosRecorder(std::vector<std::unique_ptr<MessageSink>> sinks, double map_every_s,
                         const slam::GridOptions& grid)
    : sinks_(std::move(sinks)), map_every_s_(map_every_s), grid_options_(grid), grid_(slam::EmptyGrid(grid)) {}

void RosRecorder::Emit(const std::string& topic, const std::string& type, Origin origin, Stamp t,
                       const std::vector<uint8_t>& cdr) {
  for (auto& sink : sinks_) sink->Write(topic, type, origin, t, cdr);
  ++counts_[topic];
}

void RosRecorder::Tf(Stamp t, const std::string& parent, const std::string& child, const CPose3D& pose, Origin origin) {
  const io::ros::TransformStamped tf{{t, parent}, child, io::ros::FromMrpt(pose)};
  Emit("/tf", io::ros::kTfMessageType, origin, t, io::ros::Encode(std::vector<io::ros::TransformStamped>{tf}));
}

void RosRecorder::Observation(Stamp t, const mrpt::obs::CObservation::Ptr& o) {
  if (const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) {
    const std::string frame = io::ros::FrameName(scan->sensorLabel);
    if (mounted_.insert(frame).second) {
      mounts_.push_back({{t, kBase}, frame, io::ros::FromMrpt(scan->sensorPose)});
      Emit("/tf_static", io::ros::kTfMessageType, Origin::kInput, t, io::ros::Encode(mounts_));
    }
    Emit("/scan", io::ros::kLaserScanType, Origin::kInput, t, io::ros::Encode(io::ros::FromMrpt(*scan, t, frame)));
  } else if (const auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
    odom_from_base_ = CPose3D(odo->odometry.x(), odo->odometry.y(), 0, odo->odometry.phi(), 0, 0);
    Emit("/odom", io::ros::kOdometryType, Origin::kInput, t, io::ros::Encode(io::ros::FromMrpt(*odo, t, kOdom, kBase)));
    Tf(t, kOdom, kBase, odom_from_base_, Origin::kInput);
  } else if (const auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(o)) {
    Emit("/imu", io::ros::kImuType, Origin::kInput, t, io::ros::Encode(io::ros::FromMrpt(*imu, t, kBase)));
  }
}

void RosRecorder::Pose(Stamp t, const CPose3D& map_from_base) {
  // map → odom = (map → base) ⊕ (odom → base)⁻¹, with the latest odometry.
  Tf(t, kMap, kOdom, map_from_base + (-odom_from_base_), Origin::kEstimate);
}

void RosRecorder::Keyframes(const std::vector<slam::Keyframe>& keyframes, bool moved, Stamp t) {
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

void RosRecorder::Map(const mrpt::maps::COccupancyGridMap2D& grid, Stamp t) {
  Emit("/map", io::ros::kOccupancyGridType, Origin::kEstimate, t, io::ros::Encode(ToRos(grid, t)));
  last_map_s_ = t.Seconds();
}

std::map<std::string, uint64_t> RosRecorder::Counts() const { return counts_; }

void RosRecorder::Path(const std::string& topic, const std::vector<CPose3D>& poses, Stamp t) {
  io::ros::Path path;
  path.header = {t, kMap};
  for (const auto& p : poses) path.poses.push_back({{t, kMap}, io::ros::FromMrpt(p)});
  Emit(topic, io::ros::kPathType, Origin::kEstimate, t, io::ros::Encode(path));
}

void RosRecorder::Poses(const std::string& topic, const std::vector<CPose3D>& poses, Stamp t) {
  io::ros::PoseArray array;
  array.header = {t, kMap};
  for (const auto& p : poses) array.poses.push_back(io::ros::FromMrpt(p));
  Emit(topic, io::ros::kPoseArrayType, Origin::kEstimate, t, io::ros::Encode(array));
}

void RosRecorder::Finish(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& trajectory, Stamp end) {
  Map(grid, end);
  io::ros::Path path;
  path.header = {end, kMap};
  for (const auto& p : trajectory) path.poses.push_back({{p.stamp, kMap}, io::ros::FromMrpt(p.pose)});
  Emit("/trajectory", io::ros::kPathType, Origin::kEstimate, end, io::ros::Encode(path));
  for (auto& sink : sinks_) sink->Close();
}

}  // namespace specht::pipeline::internal
