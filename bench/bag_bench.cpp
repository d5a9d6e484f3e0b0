// bag_bench <data dir>: reading ROS recordings, on one core — MB of message payloads
// decoded per second, each case repeated until ≥ 1 s of work.
//   ros2_bag_to_observations  the TurtleBot 4 bag (rosbag2 sqlite3): SQLite, Fast CDR,
//                             MRPT observations (scans with their mounts, odometry)
//   mcap_decode               the same messages written to an MCAP (zstd chunks) and
//                             read back: records, decompression, CDR decoding
//   mcap_to_observations      that MCAP through the dataset source (as `specht slam
//                             run.mcap` reads it)
#include <chrono>
#include <filesystem>

#include "bench_support.h"
#include "specht/io/mcap.h"
#include "specht/io/ros_bag.h"
#include "specht/io/ros_conversion.h"
#include "specht/io/ros_messages.h"

namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Runs `pass` (returns payload bytes) until ≥ 1 s; emits MB/s.
template <class Pass>
void Measure(const std::string& name, Pass pass) {
  double bytes = 0;
  int passes = 0;
  const auto t0 = Clock::now();
  while (Since(t0) < 1.0) bytes += pass(), ++passes;
  const double s = Since(t0);
  specht::bench::Emit({{"bench", "bag"},
                       {"case", name},
                       {"passes", passes},
                       {"payload_mb", bytes / passes / 1e6},
                       {"mb_per_s", bytes / s / 1e6},
                       {"machine", specht::bench::MachineNotes()}});
}

}  // namespace

int main(int argc, char** argv) {
  namespace io = specht::io;
  const std::string data = argc > 1 ? argv[1] : SPECHT_DATA_DIR;
  const std::string bag = data + "/ros/turtlebot4-mac-first-floor";
  if (!io::IsRos2Bag(bag)) {
    std::fprintf(stderr, "bag_bench: no ROS 2 bag at %s\n", bag.c_str());
    return 2;
  }
  // The bag's scans and odometry as CDR again, into an MCAP (untimed).
  const std::string mcap = (std::filesystem::temp_directory_path() / "specht_bag_bench.mcap").string();
  double payload = 0;
  {
    io::McapWriter w(mcap);
    const auto scan_ch = w.AddChannel(w.AddSchema(io::ros::kLaserScanType, "ros2msg", ""), "/scan", "cdr");
    const auto odom_ch = w.AddChannel(w.AddSchema(io::ros::kOdometryType, "ros2msg", ""), "/odom", "cdr");
    auto source = io::OpenRos2Bag(bag);
    while (auto o = source->Next()) {
      std::vector<uint8_t> cdr;
      if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o->data))
        w.Write(scan_ch, o->stamp.ns, cdr = io::ros::Encode(io::ros::FromMrpt(*s, o->stamp, "laser")));
      else if (auto d = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o->data))
        w.Write(odom_ch, o->stamp.ns, cdr = io::ros::Encode(io::ros::FromMrpt(*d, o->stamp, "odom", "base_link")));
      payload += cdr.size();
    }
    w.Close();
  }
  Measure("ros2_bag_to_observations", [&] {
    auto source = io::OpenRos2Bag(bag);
    while (source->Next()) {
    }
    return payload;
  });
  Measure("mcap_decode", [&] {
    io::McapReader r(mcap);
    double bytes = 0;
    while (auto m = r.Next()) {
      bytes += m->data.size();
      if (m->topic == "/scan")
        io::ros::DecodeLaserScan(m->data);
      else
        io::ros::DecodeOdometry(m->data);
    }
    return bytes;
  });
  Measure("mcap_to_observations", [&] {
    auto source = io::OpenMcap(mcap);
    while (source->Next()) {
    }
    return payload;
  });
  std::filesystem::remove(mcap);
  return 0;
}
