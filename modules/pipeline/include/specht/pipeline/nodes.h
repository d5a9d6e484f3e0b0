// specht/pipeline/nodes.h: the stack's stages as DDS nodes that speak ROS 2 (net/:
// Cyclone DDS, ROS 2's topic and type names, the CDR io/ros_messages.h encodes), so
// that a stage runs in its own process or on another computer, and ROS 2 nodes can
// feed it or listen to it without a bridge.
//   play  a dataset (any file `specht slam` reads) published as a robot's drivers
//         would: /scan (sensor_msgs/LaserScan), /odom (nav_msgs/Odometry), /tf
//         (odom → base_link), /tf_static (base_link → each scan frame), and /clock
//         (rosgraph_msgs/Clock: the data time, for ROS 2 nodes with use_sim_time),
//         paced by replay.rate, reliable and keep-all so that no message is lost
//   slam  graph SLAM (pipeline/replay.h) on /scan, /odom and /tf_static, publishing
//         /map (latched, every node.map_every_s of data), /tf (map → odom) and, at
//         the end, /trajectory; it writes what `specht slam` writes (map artefact,
//         trajectory, report) when its input ends (node.idle_end_s of silence) or a
//         signal stops it
//   record  the ROS 2 topics specht speaks (/scan, /odom, /tf, /tf_static, /map,
//         /trajectory, /path, /tracks), from specht's nodes or any ROS 2 node, into
//         an MCAP file (ROS 2 schemas) in source-time order, the bytes as they came;
//         `specht slam run.mcap` replays it
// A node's configuration is the same parameter files' sections "dds" (net/dds.h:
// domain, interface, peers) and "node" (below).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/net/dds.h"

namespace specht::pipeline {

// Section "node".
struct NodeOptions {
  std::string scan_topic = "/scan";
  std::string odometry_topic = "/odom";
  double settle_s = 0.2;
  double idle_end_s = 0;
  double map_every_s = 1.0;
  double wait_for_subscriber_s = 10;
  int subscribers = 1;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("scan_topic", scan_topic, "the sensor_msgs/msg/LaserScan topic a node reads or publishes");
    v.Param("odometry_topic", odometry_topic, "the nav_msgs/msg/Odometry topic; \"none\" = SLAM reads no odometry");
    v.Param("settle_s", settle_s,
            "a message waits at most this long for the other topics' before it is used (merging by source time)",
            Range::Of(0.0, 10.0));
    v.Param("idle_end_s", idle_end_s,
            "the SLAM node ends its input after this long without a message, once one came; 0 = only a signal "
            "ends it",
            Range::Of(0.0, 3600.0));
    v.Param("map_every_s", map_every_s, "the SLAM node publishes /map this often, in data time",
            Range::Of(0.1, 3600.0));
    v.Param("wait_for_subscriber_s", wait_for_subscriber_s,
            "the player waits this long for `subscribers` subscribers to its scans before it starts (then starts "
            "anyway): a subscriber that joins later misses what came before",
            Range::Of(0.0, 3600.0));
    v.Param("subscribers", subscribers, "how many subscribers to its scans the player waits for (SLAM, a recorder)",
            Range::Of(0, 100));
  }
};

struct PlayInputs {
  std::string dataset;                              // "" = the rawlog shipped by Debian's mrpt-common
  std::vector<std::string> param_files, overrides;  // recorded in the report
};

// `specht node play`: opens the dataset (InputError before anything is published),
// publishes it, writes report.json into `out_dir`. Returns 0, 2 when the input broke
// off, 128 + the signal when interrupted.
int PlayDataset(const params::Params& params, const PlayInputs& inputs, const std::string& out_dir, bool quiet);

struct RecordInputs {
  std::string mcap = "run.mcap";  // a bare file name goes into the output folder
  std::vector<std::string> param_files, overrides;
};

// `specht node record`: records until node.idle_end_s of silence or a signal, then
// closes the file and writes report.json (messages by topic). Returns 0, 2 when
// nothing came, 128 + the signal when interrupted.
int RecordTopics(const params::Params& params, const RecordInputs& inputs, const std::string& out_dir, bool quiet);

// The participant a node joins, from section "dds".
std::shared_ptr<net::Participant> NodeParticipant(const params::Params& params);

}  // namespace specht::pipeline
