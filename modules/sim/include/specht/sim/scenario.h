// specht/sim/scenario.h: synthetic worlds with ground truth, described in YAML
// (datasets/scenarios/*.yaml). A scenario holds
//   world:   bounds, static objects as 2D polygons with heights and textures (walls,
//            parked cars, cones, road boundaries) and marked parking bays;
//   ego:     the car (bicycle model: wheelbase, steering and speed limits) and the
//            route it follows;
//   agents:  moving pedestrians, cyclists and cars, each following a route with its
//            class's motion model (motion.h);
//   sensors: 2D LiDAR, wheel odometry, IMU, with mounts and noise;
//   seed, duration_s.
// Loading validates everything and reports each problem as
// "file:line: key: reason" (unknown keys get the nearest valid one suggested):
// wrong types, out-of-range values (negative speeds), self-intersecting polygons,
// starts and waypoints outside the world, and route legs that pass through a solid
// object (a building, a parked car, a cone).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace specht::sim {

struct Vec2 {
  double x = 0, y = 0;
};

struct Pose2 {
  double x = 0, y = 0, yaw_rad = 0;
};

enum class ObjectType { kWall, kParkedCar, kCone, kBoundary, kBuilding };

struct StaticObject {
  ObjectType type = ObjectType::kWall;
  std::vector<Vec2> polygon;  // closed; a wall may be a polyline of 2+ points
  bool closed = true;
  double height_m = 1.0;
  std::string texture = "noise";
};

struct ParkingBay {
  std::string name;
  Pose2 pose;  // centre, heading along the bay
  double length_m = 5.0, width_m = 2.5;
};

struct VehicleModel {
  double wheelbase_m = 1.6;
  double max_steer_rad = 0.5;
  double max_speed_mps = 5.0;
  double max_accel_mps2 = 1.5;
  double length_m = 2.5, width_m = 1.3;
  // Rear bumper behind the point the car turns about (its rear axle); the pose is
  // the box centre, length/2 − rear_overhang ahead of it. Default length/2: the
  // car turns about its box centre (the scenarios before this key were tuned so);
  // a real car's is (length − wheelbase)/2 or so, which lets it tuck into a
  // parallel slot.
  double rear_overhang_m = 1.25;
  double PivotAhead() const { return length_m / 2 - rear_overhang_m; }
};

struct Waypoint {
  Vec2 p;
  bool stop = false;  // cars stop here (a crossing); pedestrians may pause anywhere
};

struct Ego {
  VehicleModel model;
  Pose2 start;
  std::vector<Waypoint> route;
  double cruise_speed_mps = 3.0;
  bool loop = true;
};

enum class AgentClass { kPedestrian, kCyclist, kCar };
const char* Name(AgentClass c);

struct AgentSpec {
  int id = 0;
  AgentClass cls = AgentClass::kPedestrian;
  std::vector<Waypoint> route;
  double start_s = 0;
  bool loop = false;         // closed route; otherwise back and forth along it
  double max_speed_mps = 0;  // caps the class's sampled cruise speed (0 = no cap)
  std::string sprite;        // the sprite the camera shows (sprites.h names); "" = chosen by the view
};

struct LidarSpec {
  double rate_hz = 10;
  int beams = 361;
  double fov_rad = M_PI;
  double max_range_m = 30;
  double range_noise_m = 0.01;
  double dropout = 0.01;
  Pose2 mount;  // on base_link
};

struct OdometrySpec {
  double rate_hz = 50;
  double translation_noise = 0.02;    // std. dev. per metre travelled (fraction)
  double rotation_noise = 0.02;       // std. dev. per radian turned (fraction)
  double rotation_per_metre = 0.002;  // rad of yaw drift per metre, systematic
};

struct ImuSpec {
  double rate_hz = 100;
  double gyro_noise_rad_s = 0.002;
  double gyro_bias_rad_s = 0.003;
  double accel_noise_mps2 = 0.05;
};

// A rectified stereo camera (rendered by camera.h).
struct StereoSpec {
  double rate_hz = 2;
  int width = 640, height = 240;
  double focal_px = 400;
  double baseline_m = 0.4;
  double x_m = 0.5, y_m = 0, z_m = 1.3, yaw_rad = 0, pitch_rad = 0;  // mount on base_link
  std::string sprites = "all";  // the sprite set agents are drawn from: tuning, held_out, all
};

struct Scenario {
  std::string path;  // the file it came from
  std::string name;
  uint64_t seed = 1;
  double duration_s = 60;
  std::array<double, 4> bounds{0, 0, 50, 50};  // xmin ymin xmax ymax
  std::vector<StaticObject> objects;
  std::vector<ParkingBay> bays;
  Ego ego;
  std::vector<AgentSpec> agents;
  LidarSpec lidar;
  OdometrySpec odometry;
  ImuSpec imu;
  std::optional<StereoSpec> stereo;  // rendered only when the scenario has one
};

// Throws InputError with one line per problem.
Scenario LoadScenario(const std::string& path);
Scenario ParseScenario(const std::string& yaml, const std::string& source_name);

}  // namespace specht::sim
