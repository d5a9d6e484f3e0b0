// specht/io/ros_conversion.h: ROS messages (ros_messages.h) to MRPT observations and
// back, for every source and sink that speaks ROS (bags, MCAP).
//
// Into MRPT (RosObservations):
//   LaserScan  a CObservation2DRangeScan, mounted where /tf_static puts its frame on
//              the base frame (odometry's child frame, else base_link); beams outside
//              [range_min, range_max] invalid; a scan not centred on its x axis is
//              rotated by its mid angle (MRPT's scans are symmetric about it)
//   Odometry   a CObservationOdometry (x, y, yaw; the twist as its local velocity)
//   Imu        a CObservationIMU: angular velocity and linear acceleration (its
//              orientation, when it carries one, is not read)
// Out of MRPT: the same fields; an invalid beam becomes +inf (above range_max).
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3D.h>

#include <map>
#include <string>
#include <vector>

#include "specht/io/dataset.h"
#include "specht/io/ros_messages.h"

namespace specht::io::ros {

mrpt::poses::CPose3D ToMrpt(const Pose& p);
Pose FromMrpt(const mrpt::poses::CPose3D& p);

LaserScan FromMrpt(const mrpt::obs::CObservation2DRangeScan& scan, Stamp stamp, const std::string& frame_id);
Odometry FromMrpt(const mrpt::obs::CObservationOdometry& odometry, Stamp stamp, const std::string& odom_frame,
                  const std::string& base_frame);
// The IMU's rates and accelerations (the components it holds; the others zero), no
// orientation (orientation_covariance[0] = -1, as REP-145 marks it).
Imu FromMrpt(const mrpt::obs::CObservationIMU& imu, Stamp stamp, const std::string& frame_id);

// A TF frame name for a sensor label ("/scan" → "scan"; "" → "laser").
std::string FrameName(const std::string& label);

// A message that did not decode or convert (`why`): with kStop a DatasetError naming
// the file, the message's index and its topic; with kSkip the same line in `skipped`.
void OnBadMessage(OnBadRecord on_bad, const std::string& file, int64_t index, const std::string& topic,
                  const std::string& why, std::vector<std::string>& skipped);

class RosObservations {
 public:
  // /tf_static transforms, before the scans that need them.
  void AddStatic(const std::vector<TransformStamped>& transforms);
  // `topic` labels the observation; `received_ns` stamps a message whose header has none.
  mrpt::obs::CObservation2DRangeScan::Ptr Scan(const LaserScan& m, const std::string& topic);
  mrpt::obs::CObservationOdometry::Ptr Odometry(const ros::Odometry& m, const std::string& topic);
  static mrpt::obs::CObservationIMU::Ptr Imu(const ros::Imu& m, const std::string& topic);
  static Stamp StampOf(const Header& h, int64_t received_ns) { return h.stamp.ns > 0 ? h.stamp : Stamp{received_ns}; }
  // The same as dataset observations, stamped by their headers (else `received_ns`),
  // `index` naming the message in its recording.
  Observation Observe(const LaserScan& m, const std::string& topic, int64_t received_ns, int64_t index);
  Observation Observe(const ros::Odometry& m, const std::string& topic, int64_t received_ns, int64_t index);
  // Notes for the report: scan frames with no /tf_static path to the base frame.
  std::vector<std::string> MountNotes() const;

 private:
  mrpt::poses::CPose3D Mount(const std::string& frame);
  std::string base_ = "base_link";
  std::map<std::string, std::pair<std::string, mrpt::poses::CPose3D>> parent_of_;  // child → (parent, pose)
  std::map<std::string, bool> mounted_;
};

}  // namespace specht::io::ros
