#include "specht/io/ros_messages.h"

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>

#include <cmath>

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
  return Decode<LaserScan>(payload, "sensor_msgs/msg/LaserScan", [](Cdr& cdr, LaserScan& m) {
    Read(cdr, m.header);
    cdr >> m.angle_min >> m.angle_max >> m.angle_increment >> m.time_increment >> m.scan_time >> m.range_min >>
        m.range_max >> m.ranges >> m.intensities;
  });
}

Odometry DecodeOdometry(const std::vector<uint8_t>& payload) {
  return Decode<Odometry>(payload, "nav_msgs/msg/Odometry", [](Cdr& cdr, Odometry& m) {
    Read(cdr, m.header);
    cdr >> m.child_frame_id;
    ReadPose(cdr, m.pose);
    cdr >> m.pose_covariance;
    cdr >> m.vx >> m.vy >> m.vz >> m.wx >> m.wy >> m.wz;
    cdr >> m.twist_covariance;
  });
}

std::vector<TransformStamped> DecodeTfMessage(const std::vector<uint8_t>& payload) {
  return Decode<std::vector<TransformStamped>>(payload, "tf2_msgs/msg/TFMessage", [](Cdr& cdr, auto& out) {
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

}  // namespace specht::io::ros
