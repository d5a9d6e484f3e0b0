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
//   sim   the simulated car and its world (a scenario): /scan, /odom, /imu, /tf, /tf_static,
//         /clock and /ground_truth (nav_msgs/Odometry: the ego's true pose, the
//         simulator's box centre, frame "map") out; ackermann_msgs/msg/
//         AckermannDriveStamped commands in (node.command_topic, /drive as on
//         F1TENTH cars). In lockstep (node.lockstep) the simulated clock stops at
//         every control step (closed_loop.control_hz) until a command stamped with
//         that step's time came: before it publishes /clock of a step, every reader
//         has acknowledged the sensor messages up to it, so the commander decides on
//         all of them, however slow either side is, and the drive is the same on
//         every run. Without lockstep it runs paced by replay.rate and applies the
//         latest command, as a car would. Ends at the scenario's duration
//         (--duration) or on a signal; writes ground_truth.tum and report.json
//   stack the closed loop's stack (pipeline/closed_loop.h: SLAM localisation, the
//         tracker on the car's detections, the world model, the planners and the
//         mission state machine) on the simulated car's topics, in lockstep with the
//         run that started it (`specht run --nodes`): /scan, /odom, /imu, /tf_static,
//         /detections (specht_msgs/Obstacles) and /vehicle_state
//         (specht_msgs/VehicleState: the car's speed and steering angle, asking for
//         a control step's command) in; /stack/step (specht_msgs/StackStep: the
//         command and what it was decided on), /perception/tracks and /drive out.
//         Writes stack.json (its figures, for the run), map/ after a mapping drive,
//         and report.json when the car says the drive ended. With a perception node
//         (--perception-node) it tracks nothing itself: for each detector frame it
//         publishes the pose it believes on /localization/odometry and waits (at
//         most node.perception_wait_s, and only while a perception node is there)
//         for that frame's tracks; without them the frame is missing, and the
//         mission state machine's perception timeout (closed_loop.blind_slow_s,
//         blind_stop_s) slows, then stops the car until frames come again
//   perception  the tracker of the stack as a node of its own: /detections and
//         /localization/odometry in, /perception/tracks (specht_msgs/Tracks) and
//         /perception/obstacles (map frame) out; ends with the drive
//         (/vehicle_state), on a signal, or after node.command_timeout_s of silence
//   record  the ROS 2 topics specht speaks (/scan, /odom, /tf, /tf_static, /map,
//         /trajectory, /path, /tracks), from specht's nodes or any ROS 2 node, into
//         an MCAP file (ROS 2 schemas) in source-time order, the bytes as they came;
//         `specht slam run.mcap` replays it
// A node's configuration is the same parameter files' sections "dds" (net/dds.h:
// domain, interface, peers) and "node" (below).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/trajectory.h"
#include "specht/net/dds.h"
#include "specht/sim/scenario.h"
#include "specht/sim/simulator.h"

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
  std::string command_topic = "/drive";
  bool lockstep = true;
  double command_timeout_s = 10;
  double perception_wait_s = 1.0;
  double perception_lease_s = 1.0;

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
    v.Param("command_topic", command_topic,
            "the ackermann_msgs/msg/AckermannDriveStamped topic the simulator node drives the car by");
    v.Param("lockstep", lockstep,
            "the simulator node stops its clock at every control step until that step's command came (a drive "
            "the same on every run); off: paced by replay.rate, the latest command applies");
    v.Param("command_timeout_s", command_timeout_s,
            "in lockstep, the simulator node ends (status incomplete) when a step's command has not come after "
            "this long",
            Range::Of(0.1, 3600.0));
    v.Param("perception_wait_s", perception_wait_s,
            "the stack node waits this long (wall clock) for a perception node's tracks of a detector frame, then "
            "goes on without them",
            Range::Of(0.01, 60.0));
    v.Param("perception_lease_s", perception_lease_s,
            "`run --nodes --perception-node` starts the perception node with this DDS lease (dds.lease_s): a "
            "killed perception node is noticed as gone within it",
            Range::Of(0.2, 60.0));
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

struct SimNodeInputs {
  std::string scenario;              // a scenario file (datasets/scenarios/*.yaml)
  std::optional<uint64_t> seed;      // default: the scenario's
  std::optional<double> duration_s;  // default: the scenario's
  std::vector<std::string> param_files, overrides;
};

// `specht node sim`: drives the scenario's car by the commands on node.command_topic
// (above), writes ground_truth.tum and report.json. Returns 0, 1 when the commands
// stopped coming (lockstep), 128 + the signal when interrupted.
int RunSimulatorNode(const params::Params& params, const SimNodeInputs& inputs, const std::string& out_dir, bool quiet);

struct StackNodeInputs {
  std::string scenario;          // the site: static map, bays, the car's dimensions
  std::string mission;           // mission file, or "" (park in the first bay)
  std::string map_dir;           // a mapping drive's map to localise on, or ""
  std::string mcap;              // record the drive into this MCAP file, or ""
  std::optional<uint64_t> seed;  // default: the scenario's
  bool perception_node = false;  // the tracker runs in `specht node perception`
  std::vector<std::string> param_files, overrides;
};

// `specht node stack`: returns 0 when the drive ended, 1 when the car fell silent
// for node.command_timeout_s, 128 + the signal when interrupted.
int RunStackNode(const params::Params& params, const StackNodeInputs& inputs, const std::string& out_dir, bool quiet);

struct PerceptionNodeInputs {
  std::vector<std::string> param_files, overrides;  // recorded in the report
};

// `specht node perception`: returns 0 when the drive ended, 1 after
// node.command_timeout_s of silence, 128 + the signal when interrupted.
int RunPerceptionNode(const params::Params& params, const PerceptionNodeInputs& inputs, const std::string& out_dir,
                      bool quiet);

// The simulator node's loop, commands from a function: at each control step of
// `control_hz`, `command(t)` gives the car's command for the step starting at t
// (nullopt ends the drive), then the simulator runs to the next step, handing each
// observation to `observe`. Returns the ego's true pose (box centre) at every control
// step; stops early on a signal.
using CommandAt = std::function<std::optional<sim::Simulator::EgoCommand>(Stamp t, const sim::Simulator& sim)>;
Trajectory DriveSimulatedCar(sim::Simulator& sim, double duration_s, double control_hz, const CommandAt& command,
                             const sim::Simulator::Sink& observe);

// What the simulator does with a drive command: speed and steering angle as sent
// (float32 on the wire), steering_angle_velocity 0 meaning the car's own limit.
sim::Simulator::EgoCommand EgoCommandOf(float speed_mps, float steer_rad, float steer_rate_rad_s,
                                        double max_steer_rate_rad_s);

// The participant a node joins, from section "dds".
std::shared_ptr<net::Participant> NodeParticipant(const params::Params& params);

}  // namespace specht::pipeline
