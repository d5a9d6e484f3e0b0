// specht/net/dds.h: specht's messages over DDS, the middleware under ROS 2, on
// Eclipse Cyclone DDS 0.10 (Debian's cyclonedds-dev), with ROS 2's naming and wire
// conventions so that a ROS 2 node on the same network and specht see each other's
// topics without a bridge:
//   topic  "/scan"                      → DDS topic "rt/scan"
//   type   "sensor_msgs/msg/LaserScan"  → DDS type  "sensor_msgs::msg::dds_::LaserScan_"
//   payload: CDR (XCDR1, little-endian, 4-byte encapsulation header), the very bytes
//   io/ros_messages.h encodes and decodes for bags and MCAP: one serialization, three
//   uses. The IDL of every type (modules/net/idl) is compiled by idlc at build time;
//   Cyclone checks each payload against it before it leaves the process.
//
// Tests and benchmarks must send nothing beyond this machine: the default Options
// bind DDS to the loopback interface, turn multicast off and list the peers (this
// machine) explicitly; `trace_file` makes Cyclone write the configuration it really
// uses, which the tests read back.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/time.h"

namespace specht::net {

// Section "dds".
struct Options {
  int domain = 0;
  std::string interface_address = "127.0.0.1";
  std::vector<std::string> peers = {"127.0.0.1"};
  int max_participants = 20;
  int heartbeat_ms = 2;
  double lease_s = 10;
  std::string trace_file;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("domain", domain, "DDS domain id, as ROS_DOMAIN_ID: nodes see each other only within one",
            Range::Of(0, 232));
    v.Param("interface_address", interface_address,
            "the one network interface DDS binds to (IPv4); 127.0.0.1 keeps everything on this machine");
    v.Param("peers", peers,
            "the hosts discovery asks (IPv4; multicast is off): this machine, and the other computers of a "
            "multi-computer setup");
    v.Param("max_participants", max_participants,
            "participant indices discovery probes on each peer (how many specht or ROS 2 processes a host runs)",
            Range::Of(1, 120));
    v.Param("heartbeat_ms", heartbeat_ms,
            "a writer with samples not yet acknowledged asks its readers for acks this often (Cyclone's default: "
            "100): how long a lockstep step waits for its sensor messages to be acknowledged",
            Range::Of(1, 1000));
    v.Param("lease_s", lease_s,
            "a participant silent this long counts as gone: its readers stop holding up reliable writers and its "
            "writers are unmatched (Cyclone's default: 10)",
            Range::Of(0.2, 3600.0));
    v.Param("trace_file", trace_file, "when set, Cyclone DDS writes the configuration it runs with there");
  }
  // The relations a range cannot state: the addresses are IPv4, a peer is listed.
  std::vector<std::string> Relations() const;
  // Throws InputError naming the field ("dds.<key>") and the reason.
  void Validate() const;
};

// The Cyclone DDS XML configuration for `options` (validated).
std::string CycloneConfig(const Options& options);

// ROS 2's quality of service by kind of topic (rclcpp's profiles, Humble):
//   kDefault    reliable, volatile, keep last 10 (commands, odometry, paths)
//   kSensorData best effort, volatile, keep last 5 (scans, images)
//   kLatched    reliable, transient local, keep last 1 (/map, /tf_static: a late
//               joiner gets the latest sample)
//   kClock      best effort, volatile, keep last 1 (/clock)
//   kKeepAll    reliable, volatile, keep all: nothing is dropped; a writer waits (at
//               most 1 s a sample) for a reader that falls behind (replays, whose
//               result must not depend on the machine's speed)
//   kLatchedKeepAll  reliable, transient local, keep all: a reader that wants every
//               sample of a latched topic and, joining late, the latest one (a recorder)
enum class Qos { kDefault, kSensorData, kLatched, kClock, kKeepAll, kLatchedKeepAll };

// ROS 2's convention by topic: /map and /tf_static latched, /clock as kClock, the
// rest `stream`.
Qos QosForTopic(const std::string& ros_topic, Qos stream);

std::string DdsTopicName(const std::string& ros_topic);  // "/scan" → "rt/scan"
std::string DdsTypeName(const std::string& ros_type);    // throws InputError for a type not in the IDL

// The ROS 2 types specht carries: sensor_msgs/msg/LaserScan, nav_msgs/msg/Odometry,
// nav_msgs/msg/OccupancyGrid, nav_msgs/msg/Path, tf2_msgs/msg/TFMessage,
// geometry_msgs/msg/PoseArray, rosgraph_msgs/msg/Clock,
// ackermann_msgs/msg/AckermannDriveStamped, sensor_msgs/msg/Imu, and specht's own
// specht_msgs/msg/Obstacles, VehicleState, StackStep and Tracks (io/ros_messages.h).
std::vector<std::string> SupportedTypes();

// One DDS domain participant; writers and readers belong to one. The domain's
// configuration is set by the first participant of a process on that domain.
class Participant {
 public:
  explicit Participant(const Options& options = {});
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;
  int32_t handle() const { return handle_; }
  const Options& options() const { return options_; }

 private:
  void Release();  // deletes the participant, and the domain with its last user

  Options options_;
  int32_t domain_handle_ = 0;
  int32_t handle_ = 0;
};

// Publishes CDR payloads of `ros_type` on `ros_topic`.
class Writer {
 public:
  Writer(Participant& participant, const std::string& ros_topic, const std::string& ros_type, Qos qos);
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // `cdr` with its encapsulation header; `stamp` is the sample's source time. Throws
  // InputError when the payload is not a `ros_type` (Cyclone's check against the IDL).
  void Write(const std::vector<uint8_t>& cdr, Stamp stamp);
  int MatchedReaders() const;
  // Waits until at least `n` readers matched; false when `timeout` passed first.
  bool WaitForReaders(int n, std::chrono::milliseconds timeout) const;
  // Waits until the readers acknowledged every sample written; false when `timeout` passed first.
  bool WaitForAcks(std::chrono::milliseconds timeout) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct Sample {
  std::vector<uint8_t> cdr;  // with its encapsulation header, as io::ros decodes it
  Stamp source_time;         // the writer's stamp
};

class Reader {
 public:
  Reader(Participant& participant, const std::string& ros_topic, const std::string& ros_type, Qos qos);
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  // Every sample received and not yet taken, oldest first.
  std::vector<Sample> Take();
  // Waits until a sample is there to take; false when `timeout` passed first.
  bool WaitForData(std::chrono::milliseconds timeout) const;
  int MatchedWriters() const;
  bool WaitForWriters(int n, std::chrono::milliseconds timeout) const;

 private:
  friend class WaitSet;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Waits on several readers at once.
class WaitSet {
 public:
  explicit WaitSet(Participant& participant);
  ~WaitSet();
  WaitSet(const WaitSet&) = delete;
  WaitSet& operator=(const WaitSet&) = delete;
  void Attach(const Reader& reader);  // the reader must outlive the wait set
  // Waits until one of the readers has a sample to take; false when `timeout` passed first.
  bool Wait(std::chrono::milliseconds timeout) const;

 private:
  int32_t handle_ = 0;
};

}  // namespace specht::net
