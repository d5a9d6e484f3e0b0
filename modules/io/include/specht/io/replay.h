// specht/io/replay.h: the replay clock. Observations are delivered in dataset
// order and carry dataset time; the clock only decides which ones fall inside the
// [from, to] window and, when a rate is set, sleeps so that dataset time advances
// at `rate` times the wall clock. Pacing never changes what is computed.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/time.h"

namespace specht::io {

// Section "replay".
struct ReplayOptions {
  double rate = 0.0;    // 0 = as fast as possible
  double from_s = 0.0;  // seconds after the first observation
  double to_s = 0.0;    // 0 = to the end
  std::string on_bad_record = "stop";
  std::string scan_topic, odometry_topic;  // ROS bags; "" = the first of its type
  double mcap_map_every_s = 10;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("rate", rate, "pace the replay at this multiple of real time; 0 = as fast as possible", Range::AtLeast(0));
    v.Param("from_s", from_s, "start this many seconds after the first observation", Range::AtLeast(0));
    v.Param("to_s", to_s, "stop this many seconds after the first observation; 0 = at the end", Range::AtLeast(0));
    v.Choice("on_bad_record", on_bad_record, {"stop", "skip"},
             "on a corrupt record: stop (write what was computed, mark the report incomplete) or skip it");
    v.Param("scan_topic", scan_topic, "ROS bags: the sensor_msgs/msg/LaserScan topic to map with; \"\" = the first");
    v.Param("odometry_topic", odometry_topic,
            "ROS bags: the nav_msgs/msg/Odometry topic; \"\" = the first, \"none\" = map without odometry");
    v.Param("mcap_map_every_s", mcap_map_every_s,
            "--mcap: the map (nav_msgs/OccupancyGrid) is recorded this often in data time, and at the end; 0 = "
            "only at the end",
            Range::AtLeast(0));
  }
  std::vector<std::string> Relations() const;
};

class ReplayClock {
 public:
  enum class Verdict { kBefore, kInside, kAfter };

  explicit ReplayClock(const ReplayOptions& options) : options_(options) {}

  // Where `stamp` falls relative to the window (the first stamp seen anchors it).
  Verdict Classify(Stamp stamp);
  // With a rate set, sleeps until `stamp` is due; otherwise returns at once.
  void WaitFor(Stamp stamp);

  std::optional<Stamp> first() const { return first_; }

 private:
  ReplayOptions options_;
  std::optional<Stamp> first_;
  std::optional<Stamp> pace_origin_;
  std::chrono::steady_clock::time_point wall_origin_;
};

}  // namespace specht::io
