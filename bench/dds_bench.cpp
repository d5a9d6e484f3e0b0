// dds_bench [seconds, default 10]: specht's DDS transport (net/dds.h) between two
// processes on this machine's loopback, at a SLAM node's load: 1080-beam LaserScans
// at 40 Hz and a 1024×1024 OccupancyGrid at 1 Hz, both reliable (the map latched, as
// ROS 2's map server publishes it). A child process subscribes; the latency of each
// message is its arrival time minus its source stamp (one clock: this machine's).
// Prints one JSON object per topic: sent, received, loss, latency p50 / p99 / max.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_support.h"
#include "specht/core/statistics.h"
#include "specht/io/ros_messages.h"
#include "specht/net/dds.h"

namespace {

using namespace specht;
using std::chrono::milliseconds;

constexpr int kScanHz = 40;
constexpr int kMapHz = 1;
constexpr uint32_t kMapCells = 1024;

int64_t NowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

net::Options BenchOptions() {
  net::Options o;
  o.domain = 230;  // apart from the tests' domains (1..200)
  return o;
}

io::ros::LaserScan Scan() {
  io::ros::LaserScan s;
  s.header.frame_id = "laser";
  s.angle_min = -2.35619f;
  s.angle_max = 2.35619f;
  s.angle_increment = 4.71239f / 1079;
  s.range_max = 30;
  for (int i = 0; i < 1080; ++i) s.ranges.push_back(1.f + 0.01f * static_cast<float>(i % 500));
  s.intensities.assign(1080, 100.f);
  return s;
}

io::ros::OccupancyGrid Map() {
  io::ros::OccupancyGrid g;
  g.header.frame_id = "map";
  g.resolution = 0.05f;
  g.width = g.height = kMapCells;
  g.data.assign(static_cast<size_t>(kMapCells) * kMapCells, -1);
  for (size_t i = 0; i < g.data.size(); i += 7) g.data[i] = 0;
  return g;
}

// The subscriber: receives both topics until `seconds` + 2 s have passed or both
// counts are reached, then writes "<topic> <latency ns>..." lines to `out`.
void Subscribe(double seconds, int scans_expected, int maps_expected, FILE* out) {
  net::Participant p(BenchOptions());
  net::Reader scans(p, "/scan", io::ros::kLaserScanType, net::Qos::kDefault);
  net::Reader maps(p, "/map", io::ros::kOccupancyGridType, net::Qos::kLatched);
  std::vector<int64_t> scan_ns, map_ns;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds + 5);
  while (std::chrono::steady_clock::now() < end &&
         (static_cast<int>(scan_ns.size()) < scans_expected || static_cast<int>(map_ns.size()) < maps_expected)) {
    scans.WaitForData(milliseconds(2));
    for (const auto& s : scans.Take()) scan_ns.push_back(NowNs() - s.source_time.ns);
    for (const auto& s : maps.Take()) map_ns.push_back(NowNs() - s.source_time.ns);
  }
  for (auto [name, list] : {std::pair{"/scan", &scan_ns}, std::pair{"/map", &map_ns}}) {
    std::fprintf(out, "%s", name);
    for (int64_t ns : *list) std::fprintf(out, " %lld", static_cast<long long>(ns));
    std::fprintf(out, "\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  const int scans_to_send = static_cast<int>(seconds * kScanHz);
  const int maps_to_send = static_cast<int>(seconds * kMapHz);
  int fds[2];
  if (pipe(fds) != 0) return 1;
  const pid_t child = fork();  // before any DDS entity exists in this process
  if (child == 0) {
    close(fds[0]);
    FILE* out = fdopen(fds[1], "w");
    Subscribe(seconds, scans_to_send, maps_to_send, out);
    std::fclose(out);
    _exit(0);
  }
  close(fds[1]);

  std::vector<std::pair<std::string, std::vector<double>>> latencies;  // ms
  {
    net::Participant p(BenchOptions());
    net::Writer scans(p, "/scan", io::ros::kLaserScanType, net::Qos::kDefault);
    net::Writer maps(p, "/map", io::ros::kOccupancyGridType, net::Qos::kLatched);
    if (!scans.WaitForReaders(1, milliseconds(10000)) || !maps.WaitForReaders(1, milliseconds(10000))) {
      std::fprintf(stderr, "dds_bench: the subscriber did not match within 10 s\n");
      kill(child, SIGKILL);
      return 1;
    }
    auto scan = Scan();
    auto map = Map();
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < scans_to_send; ++i) {
      std::this_thread::sleep_until(start + std::chrono::microseconds(i * 1000000 / kScanHz));
      scan.header.stamp = Stamp{NowNs()};
      scans.Write(io::ros::Encode(scan), scan.header.stamp);
      if (i % (kScanHz / kMapHz) == 0) {
        map.header.stamp = Stamp{NowNs()};
        maps.Write(io::ros::Encode(map), map.header.stamp);
      }
    }
    // The subscriber reports after it has everything (or its time is up).
    std::string text;
    char buffer[65536];
    for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<size_t>(n));
    size_t pos = 0;
    while (pos < text.size()) {
      const size_t eol = text.find('\n', pos);
      std::istringstream line(text.substr(pos, eol - pos));
      std::string name;
      line >> name;
      std::vector<double> ms;
      for (long long ns; line >> ns;) ms.push_back(static_cast<double>(ns) / 1e6);
      latencies.emplace_back(name, ms);
      pos = eol == std::string::npos ? text.size() : eol + 1;
    }
  }
  int status = 0;
  waitpid(child, &status, 0);
  for (const auto& [topic, ms] : latencies) {
    const int sent = topic == "/scan" ? scans_to_send : maps_to_send;
    const size_t bytes = topic == "/scan" ? io::ros::Encode(Scan()).size() : io::ros::Encode(Map()).size();
    specht::bench::Emit({{"bench", "dds"},
                         {"case", topic == "/scan" ? "scan_40hz_1080_beams" : "map_1hz_1024x1024"},
                         {"topic", topic},
                         {"qos", topic == "/scan" ? "reliable, keep last 10" : "reliable, transient local"},
                         {"message_bytes", bytes},
                         {"sent", sent},
                         {"received", ms.size()},
                         {"loss_percent", 100.0 * (sent - static_cast<double>(ms.size())) / sent},
                         {"latency_ms_p50", specht::Percentile(ms, 0.5)},
                         {"latency_ms_p99", specht::Percentile(ms, 0.99)},
                         {"latency_ms_max", specht::Percentile(ms, 1.0)},
                         {"machine", specht::bench::MachineNotes()}});
  }
  return 0;
}
