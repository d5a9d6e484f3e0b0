// specht/io/ros_messages.h: the ROS 2 messages specht reads from bags, and their CDR
// payloads (XCDR1 with its 4-byte encapsulation header, as rosbag2 and MCAP store
// them), decoded with eProsima Fast CDR. Field order and types follow the .msg
// definitions of sensor_msgs, nav_msgs, geometry_msgs and tf2_msgs.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "specht/core/time.h"

namespace specht::io::ros {

struct Header {  // std_msgs/msg/Header
  Stamp stamp;
  std::string frame_id;
};

struct Pose {  // geometry_msgs Point + Quaternion (or Vector3 + Quaternion in a Transform)
  double x = 0, y = 0, z = 0;
  double qx = 0, qy = 0, qz = 0, qw = 1;
  double Yaw() const;  // about z, from the quaternion
};

struct LaserScan {  // sensor_msgs/msg/LaserScan
  Header header;
  float angle_min = 0, angle_max = 0, angle_increment = 0, time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges, intensities;
};

struct Odometry {  // nav_msgs/msg/Odometry
  Header header;
  std::string child_frame_id;
  Pose pose;
  std::array<double, 36> pose_covariance{};
  double vx = 0, vy = 0, vz = 0, wx = 0, wy = 0, wz = 0;
  std::array<double, 36> twist_covariance{};
};

struct TransformStamped {  // geometry_msgs/msg/TransformStamped
  Header header;
  std::string child_frame_id;
  Pose transform;
};

// Each throws InputError naming the type and why when the payload is not one: too
// short for its fields ("ends inside"), or an encapsulation other than CDR.
LaserScan DecodeLaserScan(const std::vector<uint8_t>& cdr);
Odometry DecodeOdometry(const std::vector<uint8_t>& cdr);
std::vector<TransformStamped> DecodeTfMessage(const std::vector<uint8_t>& cdr);  // tf2_msgs/msg/TFMessage

}  // namespace specht::io::ros
