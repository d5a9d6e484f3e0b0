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

// The ROS 2 type names of the messages here, as topics, bags and schemas name them.
inline constexpr char kLaserScanType[] = "sensor_msgs/msg/LaserScan";
inline constexpr char kOdometryType[] = "nav_msgs/msg/Odometry";
inline constexpr char kTfMessageType[] = "tf2_msgs/msg/TFMessage";
inline constexpr char kOccupancyGridType[] = "nav_msgs/msg/OccupancyGrid";
inline constexpr char kPathType[] = "nav_msgs/msg/Path";
inline constexpr char kPoseArrayType[] = "geometry_msgs/msg/PoseArray";
inline constexpr char kClockType[] = "rosgraph_msgs/msg/Clock";
inline constexpr char kAckermannDriveType[] = "ackermann_msgs/msg/AckermannDriveStamped";

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

struct OccupancyGrid {  // nav_msgs/msg/OccupancyGrid
  Header header;
  Stamp map_load_time;
  float resolution = 0;
  uint32_t width = 0, height = 0;
  Pose origin;
  std::vector<int8_t> data;  // row-major from the origin; -1 unknown, 0..100 occupancy
};

struct PoseArray {  // geometry_msgs/msg/PoseArray
  Header header;
  std::vector<Pose> poses;
};

// ackermann_msgs/msg/AckermannDriveStamped: what a car-like robot is told to do (the
// F1TENTH stacks' /drive): speed and steering angle, with the rates to reach them.
struct AckermannDrive {
  Header header;
  float steering_angle = 0;           // rad, left positive
  float steering_angle_velocity = 0;  // rad/s; 0: as fast as the car can
  float speed = 0;                    // m/s, forward positive
  float acceleration = 0;             // m/s²; 0: as fast as the car can
  float jerk = 0;
};

struct Path {  // nav_msgs/msg/Path of geometry_msgs/msg/PoseStamped
  Header header;
  std::vector<std::pair<Header, Pose>> poses;
};

// Each throws InputError naming the type and why when the payload is not one: too
// short for its fields ("ends inside"), or an encapsulation other than CDR.
LaserScan DecodeLaserScan(const std::vector<uint8_t>& cdr);
Odometry DecodeOdometry(const std::vector<uint8_t>& cdr);
std::vector<TransformStamped> DecodeTfMessage(const std::vector<uint8_t>& cdr);  // tf2_msgs/msg/TFMessage
AckermannDrive DecodeAckermannDrive(const std::vector<uint8_t>& cdr);
Stamp DecodeClock(const std::vector<uint8_t>& cdr);  // rosgraph_msgs/msg/Clock

// CDR payloads (little-endian, with the encapsulation header) of the same messages,
// as rosbag2 and MCAP store them.
std::vector<uint8_t> Encode(const LaserScan& m);
std::vector<uint8_t> Encode(const Odometry& m);
std::vector<uint8_t> Encode(const std::vector<TransformStamped>& tf_message);
std::vector<uint8_t> Encode(const OccupancyGrid& m);
std::vector<uint8_t> Encode(const Path& m);
std::vector<uint8_t> Encode(const PoseArray& m);
std::vector<uint8_t> Encode(const AckermannDrive& m);
std::vector<uint8_t> EncodeClock(Stamp t);  // rosgraph_msgs/msg/Clock: the simulated time

// The ros2msg definition of `type` (e.g. "sensor_msgs/msg/LaserScan") with every
// type it uses appended, as MCAP's ros2msg schema encoding and Foxglove expect.
// Throws InputError for a type not listed here.
std::string Definition(const std::string& type);

}  // namespace specht::io::ros
