// ROS 2 message payloads (io/ros_messages.h): LaserScan, Odometry, TFMessage, AckermannDriveStamped, Clock,
// Imu and specht_msgs' Obstacles, VehicleState, StackStep and Tracks
// decoded from the input, and from every CDR encapsulation header (00 01 00 00) in
// it, so that a seed cut from a rosbag2 .db3 file feeds its real payloads in.
#include <algorithm>
#include <vector>

#include "fuzz_support.h"
#include "specht/io/ros_messages.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  constexpr uint8_t kHeader[] = {0, 1, 0, 0};
  int decoded = 0;
  for (size_t at = 0; at < size && decoded < 16; ++at) {
    if (at > 0 && (size - at < 4 || !std::equal(kHeader, kHeader + 4, data + at))) continue;
    const std::vector<uint8_t> payload(data + at, data + size);
    specht::fuzz::Expect([&] { specht::io::ros::DecodeLaserScan(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeOdometry(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeTfMessage(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeAckermannDrive(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeClock(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeImu(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeObstacles(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeVehicleState(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeStackStep(payload); });
    specht::fuzz::Expect([&] { specht::io::ros::DecodeTracks(payload); });
    ++decoded;
  }
  return 0;
}
