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
inline constexpr char kImuType[] = "sensor_msgs/msg/Imu";
// specht's own messages (package specht_msgs), between the simulated car and the
// stack of `specht run --nodes`; a ROS 2 workspace builds them from the .msg text
// Definition() gives.
inline constexpr char kObstaclesType[] = "specht_msgs/msg/Obstacles";
inline constexpr char kVehicleStateType[] = "specht_msgs/msg/VehicleState";
inline constexpr char kStackStepType[] = "specht_msgs/msg/StackStep";
inline constexpr char kTracksType[] = "specht_msgs/msg/Tracks";

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

struct Imu {  // sensor_msgs/msg/Imu; orientation_covariance[0] = -1: no orientation estimate
  Header header;
  Pose orientation;  // the quaternion only
  std::array<double, 9> orientation_covariance{}, angular_velocity_covariance{}, linear_acceleration_covariance{};
  double wx = 0, wy = 0, wz = 0;  // rad/s
  double ax = 0, ay = 0, az = 0;  // m/s²
};

// specht_msgs/msg/Obstacle: a detection or a track (types::Obstacle's fields), in the
// header's frame.
struct Obstacle {
  int64_t id = 0;
  std::string cls;
  double x = 0, y = 0, z = 0, radius = 0, length = 0, width = 0, yaw = 0;
  std::array<double, 4> covariance_xy{};  // row-major 2×2
  double score = 0, range = 0;
};
struct Obstacles {  // specht_msgs/msg/Obstacles
  Header header;
  std::vector<Obstacle> obstacles;
};

// specht_msgs/msg/VehicleState: the car's own state at a control step, which asks
// the stack for that step's command; `stop` non-empty ends the drive (the reason).
struct VehicleState {
  Header header;
  double time_s = 0;  // into the drive
  double speed_mps = 0, steer_rad = 0;
  std::string stop;
};

// specht_msgs/msg/StackStep: the stack's answer to a control step: the command at
// full precision (the /drive message carries it as float32), the pose it believes
// (box centre, map frame), its mission state, how many tracks it saw, whether it
// follows a local plan, and whether the mission is over (finished).
struct StackStep {
  Header header;
  double speed_mps = 0, steer_rad = 0;
  double x = 0, y = 0, yaw = 0;
  std::string state;
  int32_t tracks = 0;
  bool on_local_path = false, finished = false;
};

// specht_msgs/msg/Track: a tracked object in the header's frame, every field of
// types::Track (the tracker's estimate), so that a track crosses a process whole.
struct TrackPoint {  // specht_msgs/msg/TrackPoint: a filtered position
  Stamp stamp;
  double x = 0, y = 0;
};
struct PredictedPoint {  // specht_msgs/msg/PredictedPoint
  double dt = 0, x = 0, y = 0;
  std::array<double, 4> covariance_xy{};  // row-major 2×2
};
struct Track {
  int64_t id = 0;
  std::string cls;
  double x = 0, y = 0, vx = 0, vy = 0;
  std::array<double, 16> covariance{};  // row-major 4×4 over (x, y, vx, vy)
  double length = 0, width = 0, yaw = 0;
  std::string state, motion_model;
  std::vector<TrackPoint> history;
  std::vector<PredictedPoint> prediction;
  std::vector<std::string> classes;   // the trajectory classifier's, with
  std::vector<double> probabilities;  // their probabilities
};
struct Tracks {  // specht_msgs/msg/Tracks: one tracker cycle, stamped with its frame's time
  Header header;
  std::vector<Track> tracks;
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
Imu DecodeImu(const std::vector<uint8_t>& cdr);
Obstacles DecodeObstacles(const std::vector<uint8_t>& cdr);
VehicleState DecodeVehicleState(const std::vector<uint8_t>& cdr);
StackStep DecodeStackStep(const std::vector<uint8_t>& cdr);
Tracks DecodeTracks(const std::vector<uint8_t>& cdr);

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
std::vector<uint8_t> Encode(const Imu& m);
std::vector<uint8_t> Encode(const Obstacles& m);
std::vector<uint8_t> Encode(const VehicleState& m);
std::vector<uint8_t> Encode(const StackStep& m);
std::vector<uint8_t> Encode(const Tracks& m);

// The ros2msg definition of `type` (e.g. "sensor_msgs/msg/LaserScan") with every
// type it uses appended, as MCAP's ros2msg schema encoding and Foxglove expect.
// Throws InputError for a type not listed here.
std::string Definition(const std::string& type);

}  // namespace specht::io::ros
