#include "specht/io/ros_messages.h"

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>
#include <fastcdr/exceptions/NotEnoughMemoryException.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <sstream>

#include "specht/core/error.h"

namespace specht::io::ros {
namespace {

using eprosima::fastcdr::Cdr;

// Decodes one message with `read` (fields in .msg order) after the encapsulation
// header; Fast CDR's exceptions become an InputError naming the type.
template <class T, class Read>
T Decode(const std::vector<uint8_t>& payload, const char* type, Read read) {
  if (payload.size() < 4)
    throw InputError(std::string(type) + ": CDR payload of " + std::to_string(payload.size()) +
                     " bytes, shorter than its encapsulation header");
  if (payload[0] != 0 || payload[1] > 1)  // CDR_BE (0x0000) or CDR_LE (0x0001); not PL_CDR or XCDR2
    throw InputError(std::string(type) + ": unsupported CDR encapsulation 0x" + std::to_string(payload[0]) +
                     std::to_string(payload[1]));
  std::vector<char> bytes(payload.begin(), payload.end());  // FastBuffer wants a mutable buffer
  eprosima::fastcdr::FastBuffer buffer(bytes.data(), bytes.size());
  Cdr cdr(buffer, Cdr::DEFAULT_ENDIAN, Cdr::DDS_CDR);
  T message;
  try {
    cdr.read_encapsulation();
    read(cdr, message);
  } catch (const eprosima::fastcdr::exception::Exception& e) {
    throw InputError(std::string(type) + ": CDR payload of " + std::to_string(payload.size()) +
                     " bytes ends inside the message (" + e.what() + ")");
  }
  return message;
}

void Read(Cdr& cdr, Header& h) {
  int32_t sec = 0;
  uint32_t nanosec = 0;
  cdr >> sec >> nanosec >> h.frame_id;
  h.stamp = Stamp{static_cast<int64_t>(sec) * 1000000000LL + nanosec};
}

void ReadPose(Cdr& cdr, Pose& p) { cdr >> p.x >> p.y >> p.z >> p.qx >> p.qy >> p.qz >> p.qw; }

}  // namespace

double Pose::Yaw() const { return std::atan2(2 * (qw * qz + qx * qy), 1 - 2 * (qy * qy + qz * qz)); }

LaserScan DecodeLaserScan(const std::vector<uint8_t>& payload) {
  return Decode<LaserScan>(payload, kLaserScanType, [](Cdr& cdr, LaserScan& m) {
    Read(cdr, m.header);
    cdr >> m.angle_min >> m.angle_max >> m.angle_increment >> m.time_increment >> m.scan_time >> m.range_min >>
        m.range_max >> m.ranges >> m.intensities;
  });
}

AckermannDrive DecodeAckermannDrive(const std::vector<uint8_t>& payload) {
  return Decode<AckermannDrive>(payload, kAckermannDriveType, [](Cdr& cdr, AckermannDrive& m) {
    Read(cdr, m.header);
    cdr >> m.steering_angle >> m.steering_angle_velocity >> m.speed >> m.acceleration >> m.jerk;
  });
}

Stamp DecodeClock(const std::vector<uint8_t>& payload) {
  return Decode<Stamp>(payload, kClockType, [](Cdr& cdr, Stamp& t) {
    int32_t sec = 0;
    uint32_t nanosec = 0;
    cdr >> sec >> nanosec;
    t = Stamp{static_cast<int64_t>(sec) * 1000000000LL + nanosec};
  });
}

Imu DecodeImu(const std::vector<uint8_t>& payload) {
  return Decode<Imu>(payload, kImuType, [](Cdr& cdr, Imu& m) {
    Read(cdr, m.header);
    cdr >> m.orientation.qx >> m.orientation.qy >> m.orientation.qz >> m.orientation.qw >> m.orientation_covariance;
    cdr >> m.wx >> m.wy >> m.wz >> m.angular_velocity_covariance;
    cdr >> m.ax >> m.ay >> m.az >> m.linear_acceleration_covariance;
  });
}

Obstacles DecodeObstacles(const std::vector<uint8_t>& payload) {
  return Decode<Obstacles>(payload, kObstaclesType, [&](Cdr& cdr, Obstacles& m) {
    Read(cdr, m.header);
    uint32_t n = 0;
    cdr >> n;
    if (n > payload.size() / 100)  // an obstacle takes at least 100 bytes: a corrupt count
      throw InputError(std::string(kObstaclesType) + ": " + std::to_string(n) + " obstacles in a payload of " +
                       std::to_string(payload.size()) + " bytes");
    m.obstacles.resize(n);
    for (auto& o : m.obstacles)
      cdr >> o.id >> o.cls >> o.x >> o.y >> o.z >> o.radius >> o.length >> o.width >> o.yaw >> o.covariance_xy >>
          o.score >> o.range;
  });
}

VehicleState DecodeVehicleState(const std::vector<uint8_t>& payload) {
  return Decode<VehicleState>(payload, kVehicleStateType, [](Cdr& cdr, VehicleState& m) {
    Read(cdr, m.header);
    cdr >> m.time_s >> m.speed_mps >> m.steer_rad >> m.stop;
  });
}

StackStep DecodeStackStep(const std::vector<uint8_t>& payload) {
  return Decode<StackStep>(payload, kStackStepType, [](Cdr& cdr, StackStep& m) {
    Read(cdr, m.header);
    cdr >> m.speed_mps >> m.steer_rad >> m.x >> m.y >> m.yaw >> m.state >> m.tracks >> m.on_local_path >> m.finished;
  });
}

Tracks DecodeTracks(const std::vector<uint8_t>& payload) {
  // A count larger than the bytes left could hold: a corrupt payload, before it allocates.
  const auto count = [&](Cdr& cdr, size_t least_bytes, const char* what) {
    uint32_t n = 0;
    cdr >> n;
    if (n > payload.size() / least_bytes)
      throw InputError(std::string(kTracksType) + ": " + std::to_string(n) + " " + what + " in a payload of " +
                       std::to_string(payload.size()) + " bytes");
    return n;
  };
  return Decode<Tracks>(payload, kTracksType, [&](Cdr& cdr, Tracks& m) {
    Read(cdr, m.header);
    m.tracks.resize(count(cdr, 200, "tracks"));
    for (auto& t : m.tracks) {
      cdr >> t.id >> t.cls >> t.x >> t.y >> t.vx >> t.vy >> t.covariance >> t.length >> t.width >> t.yaw >> t.state >>
          t.motion_model;
      t.history.resize(count(cdr, 24, "history points"));
      for (auto& p : t.history) {
        int32_t sec = 0;
        uint32_t nanosec = 0;
        cdr >> sec >> nanosec >> p.x >> p.y;
        p.stamp = Stamp{static_cast<int64_t>(sec) * 1000000000LL + nanosec};
      }
      t.prediction.resize(count(cdr, 56, "predicted points"));
      for (auto& p : t.prediction) cdr >> p.dt >> p.x >> p.y >> p.covariance_xy;
      t.classes.resize(count(cdr, 5, "classes"));
      for (auto& c : t.classes) cdr >> c;
      t.probabilities.resize(count(cdr, 8, "probabilities"));
      for (auto& p : t.probabilities) cdr >> p;
    }
  });
}

Odometry DecodeOdometry(const std::vector<uint8_t>& payload) {
  return Decode<Odometry>(payload, kOdometryType, [](Cdr& cdr, Odometry& m) {
    Read(cdr, m.header);
    cdr >> m.child_frame_id;
    ReadPose(cdr, m.pose);
    cdr >> m.pose_covariance;
    cdr >> m.vx >> m.vy >> m.vz >> m.wx >> m.wy >> m.wz;
    cdr >> m.twist_covariance;
  });
}

std::vector<TransformStamped> DecodeTfMessage(const std::vector<uint8_t>& payload) {
  return Decode<std::vector<TransformStamped>>(payload, kTfMessageType, [](Cdr& cdr, auto& out) {
    uint32_t n = 0;
    cdr >> n;
    for (uint32_t i = 0; i < n; ++i) {
      TransformStamped t;
      Read(cdr, t.header);
      cdr >> t.child_frame_id;
      ReadPose(cdr, t.transform);
      out.push_back(std::move(t));
    }
  });
}

namespace {

// Serializes into a zeroed buffer of `size_hint` bytes, doubled and tried again when
// the message does not fit: the alignment padding CDR puts before 8-byte fields is
// then zero, as every DDS implementation writes it. (Fast CDR's own growing buffer
// left those bytes uninitialized, so two encodings of one message could differ.)
template <class Write>
std::vector<uint8_t> EncodeWith(size_t size_hint, Write write) {
  for (size_t size = std::max<size_t>(size_hint, 256);; size *= 2) {
    std::vector<char> bytes(size, 0);
    eprosima::fastcdr::FastBuffer buffer(bytes.data(), bytes.size());
    Cdr cdr(buffer, Cdr::LITTLE_ENDIANNESS, Cdr::DDS_CDR);
    try {
      cdr.serialize_encapsulation();
      write(cdr);
    } catch (const eprosima::fastcdr::exception::NotEnoughMemoryException&) {
      continue;
    }
    return {bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(cdr.getSerializedDataLength())};
  }
}

void Write(Cdr& cdr, const Header& h) {
  cdr << static_cast<int32_t>(h.stamp.ns / 1000000000) << static_cast<uint32_t>(h.stamp.ns % 1000000000) << h.frame_id;
}
void WritePose(Cdr& cdr, const Pose& p) { cdr << p.x << p.y << p.z << p.qx << p.qy << p.qz << p.qw; }

const char* const kRule = "================================================================================\n";

// The definitions, dependencies named as ros2msg schemas name them ("MSG: pkg/Type").
const std::map<std::string, std::string>& Definitions() {
  static const std::map<std::string, std::string> d = {
      {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
      {"geometry_msgs/Pose", "Point position\nQuaternion orientation\n"},
      {"geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation\n"},
      {"geometry_msgs/Twist", "Vector3 linear\nVector3 angular\n"},
      {"geometry_msgs/PoseWithCovariance", "Pose pose\nfloat64[36] covariance\n"},
      {"geometry_msgs/TwistWithCovariance", "Twist twist\nfloat64[36] covariance\n"},
      {"geometry_msgs/PoseStamped", "std_msgs/Header header\nPose pose\n"},
      {"geometry_msgs/TransformStamped", "std_msgs/Header header\nstring child_frame_id\nTransform transform\n"},
      {"nav_msgs/MapMetaData",
       "builtin_interfaces/Time map_load_time\nfloat32 resolution\nuint32 width\nuint32 height\n"
       "geometry_msgs/Pose origin\n"},
      {"sensor_msgs/LaserScan",
       "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
       "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\nfloat32[] ranges\n"
       "float32[] intensities\n"},
      {"nav_msgs/Odometry",
       "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
       "geometry_msgs/TwistWithCovariance twist\n"},
      {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
      {"nav_msgs/OccupancyGrid", "std_msgs/Header header\nMapMetaData info\nint8[] data\n"},
      {"nav_msgs/Path", "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n"},
      {"geometry_msgs/PoseArray", "std_msgs/Header header\nPose[] poses\n"},
      {"rosgraph_msgs/Clock", "builtin_interfaces/Time clock\n"},
      {"ackermann_msgs/AckermannDrive",
       "float32 steering_angle\nfloat32 steering_angle_velocity\nfloat32 speed\nfloat32 acceleration\nfloat32 jerk\n"},
      {"ackermann_msgs/AckermannDriveStamped", "std_msgs/Header header\nAckermannDrive drive\n"},
      {"sensor_msgs/Imu",
       "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\n"
       "geometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\n"
       "geometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance\n"},
      {"specht_msgs/Obstacle",
       "int64 id\nstring cls\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 radius\nfloat64 length\nfloat64 width\n"
       "float64 yaw\nfloat64[4] covariance_xy\nfloat64 score\nfloat64 range\n"},
      {"specht_msgs/Obstacles", "std_msgs/Header header\nObstacle[] obstacles\n"},
      {"specht_msgs/VehicleState",
       "std_msgs/Header header\nfloat64 time_s\nfloat64 speed_mps\nfloat64 steer_rad\nstring stop\n"},
      {"specht_msgs/StackStep",
       "std_msgs/Header header\nfloat64 speed_mps\nfloat64 steer_rad\nfloat64 x\nfloat64 y\nfloat64 yaw\n"
       "string state\nint32 tracks\nbool on_local_path\nbool finished\n"},
      {"specht_msgs/TrackPoint", "builtin_interfaces/Time stamp\nfloat64 x\nfloat64 y\n"},
      {"specht_msgs/PredictedPoint", "float64 dt\nfloat64 x\nfloat64 y\nfloat64[4] covariance_xy\n"},
      {"specht_msgs/Track",
       "int64 id\nstring cls\nfloat64 x\nfloat64 y\nfloat64 vx\nfloat64 vy\nfloat64[16] covariance\n"
       "float64 length\nfloat64 width\nfloat64 yaw\nstring state\nstring motion_model\nTrackPoint[] history\n"
       "PredictedPoint[] prediction\nstring[] classes\nfloat64[] probabilities\n"},
      {"specht_msgs/Tracks", "std_msgs/Header header\nTrack[] tracks\n"},
  };
  return d;
}

// The types a definition uses, in the order they first appear, depth first.
void Dependencies(const std::string& type, std::vector<std::string>& out) {
  const std::string package = type.substr(0, type.find('/'));
  std::istringstream lines(Definitions().at(type));
  for (std::string line; std::getline(lines, line);) {
    std::string field = line.substr(0, line.find(' '));
    field = field.substr(0, field.find('['));
    if (field.empty() || (std::islower(static_cast<unsigned char>(field[0])) && field.find('/') == std::string::npos))
      continue;  // a primitive
    const std::string dep = field.find('/') == std::string::npos ? package + "/" + field : field;
    if (std::find(out.begin(), out.end(), dep) != out.end()) continue;
    out.push_back(dep);
    Dependencies(dep, out);
  }
}

}  // namespace

std::vector<uint8_t> Encode(const LaserScan& m) {
  return EncodeWith(256 + 4 * (m.ranges.size() + m.intensities.size()), [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << m.angle_min << m.angle_max << m.angle_increment << m.time_increment << m.scan_time << m.range_min
        << m.range_max << m.ranges << m.intensities;
  });
}

std::vector<uint8_t> Encode(const Odometry& m) {
  return EncodeWith(1024, [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << m.child_frame_id;
    WritePose(cdr, m.pose);
    cdr << m.pose_covariance << m.vx << m.vy << m.vz << m.wx << m.wy << m.wz << m.twist_covariance;
  });
}

std::vector<uint8_t> Encode(const std::vector<TransformStamped>& tf) {
  return EncodeWith(128 * (tf.size() + 1), [&](Cdr& cdr) {
    cdr << static_cast<uint32_t>(tf.size());
    for (const auto& t : tf) {
      Write(cdr, t.header);
      cdr << t.child_frame_id;
      WritePose(cdr, t.transform);
    }
  });
}

std::vector<uint8_t> Encode(const OccupancyGrid& m) {
  return EncodeWith(256 + m.data.size(), [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << static_cast<int32_t>(m.map_load_time.ns / 1000000000)
        << static_cast<uint32_t>(m.map_load_time.ns % 1000000000);
    cdr << m.resolution << m.width << m.height;
    WritePose(cdr, m.origin);
    cdr << m.data;
  });
}

std::vector<uint8_t> Encode(const Path& m) {
  return EncodeWith(256 + 96 * m.poses.size(), [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << static_cast<uint32_t>(m.poses.size());
    for (const auto& [h, p] : m.poses) {
      Write(cdr, h);
      WritePose(cdr, p);
    }
  });
}

std::vector<uint8_t> Encode(const PoseArray& m) {
  return EncodeWith(256 + 64 * m.poses.size(), [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << static_cast<uint32_t>(m.poses.size());
    for (const auto& p : m.poses) WritePose(cdr, p);
  });
}

std::vector<uint8_t> Encode(const AckermannDrive& m) {
  return EncodeWith(64 + m.header.frame_id.size(), [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << m.steering_angle << m.steering_angle_velocity << m.speed << m.acceleration << m.jerk;
  });
}

std::vector<uint8_t> EncodeClock(Stamp t) {
  return EncodeWith(16, [&](Cdr& cdr) {
    cdr << static_cast<int32_t>(t.ns / 1000000000) << static_cast<uint32_t>(t.ns % 1000000000);
  });
}

std::vector<uint8_t> Encode(const Imu& m) {
  return EncodeWith(512, [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << m.orientation.qx << m.orientation.qy << m.orientation.qz << m.orientation.qw << m.orientation_covariance;
    cdr << m.wx << m.wy << m.wz << m.angular_velocity_covariance;
    cdr << m.ax << m.ay << m.az << m.linear_acceleration_covariance;
  });
}

std::vector<uint8_t> Encode(const Obstacles& m) {
  return EncodeWith(128 + 160 * m.obstacles.size(), [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << static_cast<uint32_t>(m.obstacles.size());
    for (const auto& o : m.obstacles)
      cdr << o.id << o.cls << o.x << o.y << o.z << o.radius << o.length << o.width << o.yaw << o.covariance_xy
          << o.score << o.range;
  });
}

std::vector<uint8_t> Encode(const VehicleState& m) {
  return EncodeWith(128 + m.stop.size(), [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << m.time_s << m.speed_mps << m.steer_rad << m.stop;
  });
}

std::vector<uint8_t> Encode(const StackStep& m) {
  return EncodeWith(128 + m.state.size(), [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << m.speed_mps << m.steer_rad << m.x << m.y << m.yaw << m.state << m.tracks << m.on_local_path << m.finished;
  });
}

std::vector<uint8_t> Encode(const Tracks& m) {
  size_t bytes = 128;
  for (const auto& t : m.tracks)
    bytes += 320 + 24 * t.history.size() + 64 * t.prediction.size() + 40 * t.classes.size() + t.cls.size();
  return EncodeWith(bytes, [&](Cdr& cdr) {
    Write(cdr, m.header);
    cdr << static_cast<uint32_t>(m.tracks.size());
    for (const auto& t : m.tracks) {
      cdr << t.id << t.cls << t.x << t.y << t.vx << t.vy << t.covariance << t.length << t.width << t.yaw << t.state
          << t.motion_model;
      cdr << static_cast<uint32_t>(t.history.size());
      for (const auto& p : t.history)
        cdr << static_cast<int32_t>(p.stamp.ns / 1000000000) << static_cast<uint32_t>(p.stamp.ns % 1000000000) << p.x
            << p.y;
      cdr << static_cast<uint32_t>(t.prediction.size());
      for (const auto& p : t.prediction) cdr << p.dt << p.x << p.y << p.covariance_xy;
      cdr << t.classes << t.probabilities;
    }
  });
}

std::string Definition(const std::string& type) {
  std::string key = type;
  if (const auto at = key.find("/msg/"); at != std::string::npos) key.erase(at, 4);
  if (!Definitions().count(key)) throw InputError("no ros2msg definition of " + type + " here");
  std::vector<std::string> deps;
  Dependencies(key, deps);
  std::string text = Definitions().at(key);
  for (const auto& d : deps) text += std::string(kRule) + "MSG: " + d + "\n" + Definitions().at(d);
  return text;
}

}  // namespace specht::io::ros
