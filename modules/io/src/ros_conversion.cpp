#include "specht/io/ros_conversion.h"

#include <cmath>
#include <limits>

#include "specht/core/error.h"

namespace specht::io::ros {

using mrpt::poses::CPose3D;

CPose3D ToMrpt(const Pose& p) { return CPose3D(mrpt::math::CQuaternionDouble(p.qw, p.qx, p.qy, p.qz), p.x, p.y, p.z); }

Pose FromMrpt(const CPose3D& p) {
  mrpt::math::CQuaternionDouble q;
  p.getAsQuaternion(q);
  return {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.r()};
}

LaserScan FromMrpt(const mrpt::obs::CObservation2DRangeScan& scan, Stamp stamp, const std::string& frame_id) {
  LaserScan m;
  m.header = {stamp, frame_id};
  const size_t n = scan.getScanSize();
  const float half = scan.aperture / 2, step = n > 1 ? scan.aperture / static_cast<float>(n - 1) : 0.0f;
  m.angle_min = scan.rightToLeft ? -half : half;
  m.angle_max = -m.angle_min;
  m.angle_increment = scan.rightToLeft ? step : -step;
  m.range_min = 0;
  m.range_max = scan.maxRange;
  m.ranges.resize(n);
  for (size_t i = 0; i < n; ++i)
    m.ranges[i] = scan.getScanRangeValidity(i) ? scan.getScanRange(i) : std::numeric_limits<float>::infinity();
  return m;
}

Imu FromMrpt(const mrpt::obs::CObservationIMU& imu, Stamp stamp, const std::string& frame_id) {
  Imu m;
  m.header = {stamp, frame_id};
  m.orientation_covariance[0] = -1;
  const auto get = [&](mrpt::obs::TIMUDataIndex i) { return imu.has(i) ? imu.get(i) : 0.0; };
  m.wx = get(mrpt::obs::IMU_WX), m.wy = get(mrpt::obs::IMU_WY), m.wz = get(mrpt::obs::IMU_WZ);
  m.ax = get(mrpt::obs::IMU_X_ACC), m.ay = get(mrpt::obs::IMU_Y_ACC), m.az = get(mrpt::obs::IMU_Z_ACC);
  return m;
}

Odometry FromMrpt(const mrpt::obs::CObservationOdometry& o, Stamp stamp, const std::string& odom_frame,
                  const std::string& base_frame) {
  Odometry m;
  m.header = {stamp, odom_frame};
  m.child_frame_id = base_frame;
  m.pose = FromMrpt(CPose3D(o.odometry.x(), o.odometry.y(), 0, o.odometry.phi(), 0, 0));
  if (o.hasVelocities)
    m.vx = o.velocityLocal.vx, m.vy = o.velocityLocal.vy, m.wz = o.velocityLocal.omega;
  else
    m.twist_covariance[0] = -1;  // the ROS convention for "no estimate"
  return m;
}

void OnBadMessage(OnBadRecord on_bad, const std::string& file, int64_t index, const std::string& topic,
                  const std::string& why, std::vector<std::string>& skipped) {
  if (on_bad == OnBadRecord::kStop) throw DatasetError(file, index, -1, topic + ": " + why);
  skipped.push_back(file + ":" + std::to_string(index) + ": " + topic + ": " + why);
}

std::string FrameName(const std::string& label) {
  std::string f = label;
  while (!f.empty() && f.front() == '/') f.erase(0, 1);
  for (char& c : f)
    if (c == '/') c = '_';
  return f.empty() ? "laser" : f;
}

void RosObservations::AddStatic(const std::vector<TransformStamped>& transforms) {
  for (const auto& tf : transforms) parent_of_[tf.child_frame_id] = {tf.header.frame_id, ToMrpt(tf.transform)};
}

CPose3D RosObservations::Mount(const std::string& frame) {
  CPose3D acc;
  std::string f = frame;
  for (int depth = 0; f != base_ && depth < 64; ++depth) {
    const auto it = parent_of_.find(f);
    if (it == parent_of_.end()) break;
    acc = it->second.second + acc;  // parent ← f, then f ← frame
    f = it->second.first;
  }
  mounted_[frame] = f == base_;
  return f == base_ ? acc : CPose3D();
}

std::vector<std::string> RosObservations::MountNotes() const {
  std::vector<std::string> out;
  for (const auto& [frame, mounted] : mounted_)
    if (!mounted) out.push_back("scan frame " + frame + " has no /tf_static path to the base frame: mounted at it");
  return out;
}

Observation RosObservations::Observe(const LaserScan& m, const std::string& topic, int64_t received_ns, int64_t index) {
  auto scan = Scan(m, topic);
  const Stamp t = StampOf(m.header, received_ns);
  scan->timestamp = specht::ToMrpt(t);
  return {t, scan, index};
}

Observation RosObservations::Observe(const ros::Odometry& m, const std::string& topic, int64_t received_ns,
                                     int64_t index) {
  auto odo = Odometry(m, topic);
  const Stamp t = StampOf(m.header, received_ns);
  odo->timestamp = specht::ToMrpt(t);
  return {t, odo, index};
}

mrpt::obs::CObservationOdometry::Ptr RosObservations::Odometry(const ros::Odometry& m, const std::string& topic) {
  if (!m.child_frame_id.empty()) base_ = m.child_frame_id;
  auto odo = mrpt::obs::CObservationOdometry::Create();
  odo->sensorLabel = topic;
  odo->odometry = mrpt::poses::CPose2D(m.pose.x, m.pose.y, m.pose.Yaw());
  odo->hasVelocities = m.twist_covariance[0] >= 0;
  odo->velocityLocal = {m.vx, m.vy, m.wz};
  return odo;
}

mrpt::obs::CObservationIMU::Ptr RosObservations::Imu(const ros::Imu& m, const std::string& topic) {
  auto imu = mrpt::obs::CObservationIMU::Create();
  imu->sensorLabel = topic;
  imu->timestamp = specht::ToMrpt(m.header.stamp);
  imu->set(mrpt::obs::IMU_WX, m.wx), imu->set(mrpt::obs::IMU_WY, m.wy), imu->set(mrpt::obs::IMU_WZ, m.wz);
  imu->set(mrpt::obs::IMU_X_ACC, m.ax), imu->set(mrpt::obs::IMU_Y_ACC, m.ay), imu->set(mrpt::obs::IMU_Z_ACC, m.az);
  return imu;
}

mrpt::obs::CObservation2DRangeScan::Ptr RosObservations::Scan(const LaserScan& m, const std::string& topic) {
  const size_t n = m.ranges.size();
  if (n < 2 || !(std::abs(m.angle_increment) > 0)) throw InputError("a scan of " + std::to_string(n) + " beams");
  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  scan->sensorLabel = topic;
  // The field of view is angle_max − angle_min by definition (exact for the scans
  // specht writes: ±aperture/2), the increment only its sign.
  scan->aperture = std::abs(m.angle_max - m.angle_min);
  scan->rightToLeft = m.angle_increment > 0;
  scan->maxRange = m.range_max;
  scan->resizeScan(n);
  for (size_t i = 0; i < n; ++i) {
    const float r = m.ranges[i];
    const bool valid = std::isfinite(r) && r >= m.range_min && r <= m.range_max;
    scan->setScanRange(i, valid ? r : m.range_max);
    scan->setScanRangeValidity(i, valid);
  }
  // MRPT's beams run symmetric about the sensor's x axis: turn the mount by the
  // scan's mid angle.
  const double mid = (static_cast<double>(m.angle_min) + m.angle_max) / 2;
  scan->sensorPose = Mount(m.header.frame_id) + CPose3D(0, 0, 0, mid, 0, 0);
  return scan;
}

}  // namespace specht::io::ros
