// sim_node_bench [specht binary] [simulated seconds, default 60]: the simulator node
// (`specht node sim`, pipeline/nodes.h) in lockstep with a commander in this process,
// over DDS on this machine's loopback: the course at its sensors' rates (LiDAR 10 Hz,
// odometry and IMU, no camera), commands at the control rate (20 Hz). The step
// round trip is the wall time from a command sent to the next step's /clock arriving:
// the simulator's 50 ms of simulation, the wait until every reader acknowledged the
// sensor messages, and delivery. Prints one JSON object: steps, round trip p50 / p99
// / max, the node's acknowledgement wait per step, the real-time factor.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_support.h"
#include "specht/core/process.h"
#include "specht/core/statistics.h"
#include "specht/io/ros_messages.h"
#include "specht/net/dds.h"

namespace {

using namespace specht;
using Clock = std::chrono::steady_clock;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

}  // namespace

int main(int argc, char** argv) {
  const std::string specht = argc > 1 ? argv[1] : "build/release/specht";
  const double seconds = argc > 2 ? std::stod(argv[2]) : 60.0;
  const std::string root = SPECHT_SOURCE_DIR;
  const std::string dir = std::filesystem::temp_directory_path() / ("sim_node_bench-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  net::Options options;
  options.domain = 229;  // apart from the tests' domains (1..200) and the other benchmarks'
  ChildProcess node({specht, "node", "sim", root + "/datasets/scenarios/course-loop.yaml", "--duration",
                     std::to_string(seconds), "-q", "--domain", std::to_string(options.domain), "-o", dir + "/node"},
                    dir + "/console.log");
  net::Participant participant(options);
  net::Reader clock(participant, "/clock", io::ros::kClockType, net::Qos::kClock);
  net::Reader odometry(participant, "/odom", io::ros::kOdometryType, net::Qos::kKeepAll);
  net::Reader scans(participant, "/scan", io::ros::kLaserScanType, net::Qos::kKeepAll);
  net::Writer drive(participant, "/drive", io::ros::kAckermannDriveType, net::Qos::kKeepAll);
  net::WaitSet wait(participant);
  wait.Attach(clock);
  std::vector<double> round_trip_ms;
  Stamp answered{-1};
  Clock::time_point sent{};
  const auto start = Clock::now();
  while (!node.Poll()) {
    if (!wait.Wait(std::chrono::milliseconds(200))) continue;
    for (const auto& c : clock.Take()) {
      const Stamp t = io::ros::DecodeClock(c.cdr);
      if (t <= answered) continue;
      if (answered.ns >= 0) round_trip_ms.push_back(Ms(Clock::now() - sent));
      odometry.Take();
      scans.Take();
      io::ros::AckermannDrive m;
      m.header.stamp = t;
      m.speed = 2.0f;
      m.steering_angle = static_cast<float>(0.2 * std::sin(1e-9 * static_cast<double>(t.ns % 100000000000LL)));
      drive.Write(io::ros::Encode(m), t);
      sent = Clock::now();
      answered = t;
    }
  }
  const double wall_s = Ms(Clock::now() - start) / 1e3;
  nlohmann::json report;
  std::ifstream in(dir + "/node/report.json");
  if (in) report = nlohmann::json::parse(in);
  nlohmann::json result = {
      {"bench", "node"},
      {"case", "sim_node_lockstep_course"},
      {"exit_code", *node.Poll()},
      {"simulated_s", seconds},
      {"steps", round_trip_ms.size() + 1},
      {"step_round_trip_ms",
       {{"p50", Percentile(round_trip_ms, 0.5)},
        {"p99", Percentile(round_trip_ms, 0.99)},
        {"max", round_trip_ms.empty() ? 0.0 : *std::max_element(round_trip_ms.begin(), round_trip_ms.end())}}},
      {"node_ack_wait_ms_per_step", report["timing"]["stages"]["sensors_acknowledged"].value("ms_per_call", 0.0)},
      {"messages_published", report["counts"]["published"]},
      {"real_time_factor", seconds / wall_s},
      {"machine", bench::MachineNotes()}};
  bench::Emit(result);
  std::filesystem::remove_all(dir);
  return 0;
}
