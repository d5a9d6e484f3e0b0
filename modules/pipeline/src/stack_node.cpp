// The closed loop's stack over DDS: `specht node stack` (nodes.h) and the car side's
// link to it (internal/stack_link.h), which `specht run --nodes` uses. One file owns
// the protocol:
//   car → stack  /scan, /odom, /imu, /tf, /tf_static (internal/ros_recorder.h),
//                /detections (specht_msgs/Obstacles, the car's frame) and
//                /vehicle_state (specht_msgs/VehicleState: a control step, or with
//                `stop` the end of the drive)
//   stack → car  /stack/step (specht_msgs/StackStep: the decision), /perception/tracks
//                (specht_msgs/Obstacles, map frame: the tracks of each detector frame,
//                for the referee) and /drive (ackermann_msgs/AckermannDriveStamped:
//                the command as ROS tools read it, float32)
// Lockstep: the car publishes a step's inputs, waits until the stack has acknowledged
// them, then asks for the step's decision. Every car message comes from one
// publisher, whose source times increase in publication order (net/topics.h): the
// stack handles them sorted by source time, which is the order the in-process loop
// hands them over.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "internal/ros_recorder.h"
#include "internal/stack_link.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/log.h"
#include "specht/core/process.h"
#include "specht/io/atomic_file.h"
#include "specht/io/report.h"
#include "specht/io/ros_conversion.h"
#include "specht/io/ros_messages.h"
#include "specht/net/topics.h"
#include "specht/pipeline/map_artefact.h"
#include "specht/pipeline/mission_runs.h"
#include "specht/pipeline/nodes.h"

namespace specht::pipeline {
namespace {

namespace ros = io::ros;

constexpr char kDetectionsTopic[] = "/detections";
constexpr char kVehicleStateTopic[] = "/vehicle_state";
constexpr char kStepTopic[] = "/stack/step";
constexpr char kTracksTopic[] = "/perception/tracks";
constexpr char kEndOfDrive[] = "end of drive";  // VehicleState.stop when no time limit ended it
// The car's topics, as the stack reads them.
const std::vector<std::pair<std::string, std::string>>& CarTopics() {
  static const std::vector<std::pair<std::string, std::string>> topics = {
      {"/tf_static", ros::kTfMessageType},     {"/scan", ros::kLaserScanType},
      {"/odom", ros::kOdometryType},           {"/imu", ros::kImuType},
      {kDetectionsTopic, ros::kObstaclesType}, {kVehicleStateTopic, ros::kVehicleStateType}};
  return topics;
}

ros::Obstacle ToRos(const types::Obstacle& o) {
  const auto& c = o.covariance_xy;
  return {o.id,       o.cls,      o.x_m,     o.y_m,     o.z_m,
          o.radius_m, o.length_m, o.width_m, o.yaw_rad, {c(0, 0), c(0, 1), c(1, 0), c(1, 1)},
          o.score,    o.range_m};
}

types::Obstacle FromRos(const ros::Obstacle& m, Stamp stamp) {
  types::Obstacle o;
  o.id = m.id, o.cls = m.cls, o.stamp = stamp;
  o.x_m = m.x, o.y_m = m.y, o.z_m = m.z, o.radius_m = m.radius, o.length_m = m.length, o.width_m = m.width;
  o.yaw_rad = m.yaw;
  o.covariance_xy = {m.covariance_xy[0], m.covariance_xy[1], m.covariance_xy[2], m.covariance_xy[3]};
  o.score = m.score, o.range_m = m.range;
  return o;
}

ros::Obstacles TracksToRos(const std::vector<types::Track>& tracks, Stamp stamp) {
  ros::Obstacles m{{stamp, "map"}, {}};
  for (const auto& t : tracks) {
    ros::Obstacle o;
    o.id = t.id, o.cls = t.cls, o.x = t.x_m, o.y = t.y_m, o.yaw = t.yaw_rad, o.length = t.length_m;
    o.width = t.width_m;
    m.obstacles.push_back(o);
  }
  return m;
}

std::vector<types::Track> TracksFromRos(const ros::Obstacles& m) {
  std::vector<types::Track> tracks;
  for (const auto& o : m.obstacles) {
    types::Track t;
    t.id = o.id, t.cls = o.cls, t.stamp = m.header.stamp, t.x_m = o.x, t.y_m = o.y, t.yaw_rad = o.yaw;
    t.length_m = o.length, t.width_m = o.width;
    tracks.push_back(t);
  }
  return tracks;
}

// The drive's time of a simulator stamp, as the simulator computes it (step × 10 ms).
double DriveSeconds(Stamp t) {
  return static_cast<double>((t.ns - sim::Simulator::kEpochNs) / 10'000'000LL) * sim::Simulator::kStepS;
}

// The car side's link: publishes what the car delivers, waits for the stack node's
// decisions; the node runs as a child process for one drive.
class Dds : public internal::StackLink {
 public:
  Dds(uint64_t seed, const ClosedLoopConfig& config, const ClosedLoopConfig::StackNode& node, OnTracks on_tracks)
      : node_(node),
        timeout_(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(node.timeout_s))),
        participant_(std::make_shared<net::Participant>(node.dds)),
        publisher_(std::make_shared<net::TopicPublisher>(participant_, net::Qos::kKeepAll)),
        recorder_(Sinks(publisher_), 0, config.slam.grid),
        steps_(*participant_, kStepTopic, ros::kStackStepType, net::Qos::kKeepAll),
        tracks_(*participant_, kTracksTopic, ros::kObstaclesType, net::Qos::kKeepAll),
        on_tracks_(std::move(on_tracks)),
        dir_(node.out_dir + "/stack-" + std::to_string(seed)) {
    std::filesystem::create_directories(dir_);
    std::vector<std::string> argv = node.command;
    argv.insert(argv.end(), {"--seed", std::to_string(seed), "-o", dir_});
    if (!config.mcap.empty()) argv.insert(argv.end(), {"--mcap", std::filesystem::absolute(config.mcap).string()});
    child_.emplace(argv, dir_ + "/console.log");
    // Started when it reads every topic the car publishes and answers on both of its own.
    const auto deadline = std::chrono::steady_clock::now() + timeout_;
    for (const auto& [topic, type] : CarTopics())
      while (!publisher_->WaitForReaders(topic, type, 1, std::chrono::milliseconds(100)))
        Alive("a reader of " + topic, deadline);
    while (!steps_.WaitForWriters(1, std::chrono::milliseconds(100)) ||
           !tracks_.WaitForWriters(1, std::chrono::milliseconds(100)))
      Alive("start", deadline);
  }

  void Observe(Stamp t, double, const mrpt::obs::CObservation::Ptr& observation) override {
    recorder_.Observation(t, observation);
  }

  void Detections(std::vector<types::Obstacle> in_car, Stamp stamp) override {
    ros::Obstacles m{{stamp, "base_link"}, {}};
    for (const auto& o : in_car) m.obstacles.push_back(ToRos(o));
    publisher_->Publish(kDetectionsTopic, ros::kObstaclesType, stamp, ros::Encode(m));
  }

  internal::StackDecision Control(double t_s, Stamp stamp, double speed_mps, double steer_rad) override {
    Ask({{stamp, "base_link"}, t_s, speed_mps, steer_rad, ""});
    const auto asked = std::chrono::steady_clock::now();
    const auto deadline = asked + timeout_;
    for (;;) {
      TakeTracks();
      for (const auto& sample : steps_.Take()) {
        const ros::StackStep m = ros::DecodeStackStep(sample.cdr);
        if (m.header.stamp != stamp) continue;  // an answer to another step cannot come: the stack answers in order
        answer_ms_.push_back(MsSince(asked));
        return {{m.speed_mps, m.steer_rad}, {m.x, m.y, m.yaw}, m.state, m.tracks, m.on_local_path, m.finished};
      }
      if (!steps_.WaitForData(std::chrono::milliseconds(50))) Alive("the control step at " + Seconds(t_s), deadline);
    }
  }

  void Finish(double t_s, Stamp end, const std::string& time_limit, ClosedLoopResult& r) override {
    Ask({{end, "base_link"}, t_s, 0, 0, time_limit.empty() ? kEndOfDrive : time_limit});
    const int code = child_->WaitOrKill(node_.timeout_s);
    TakeTracks();
    if (code != 0) throw RuntimeError("the stack node " + Failed(code));
    std::ifstream in(dir_ + "/stack.json");
    internal::StackFiguresFromJson(nlohmann::json::parse(in), r);
    if (std::filesystem::exists(dir_ + "/map"))
      r.drawn_map = std::make_shared<MapArtefact>(ReadMapArtefact(dir_ + "/map"));
    r.nodes = {{"stack_node", std::filesystem::path(dir_).filename().string()},
               {"domain", node_.dds.domain},
               {"acknowledged_ms", Latency(acknowledged_ms_)},
               {"answer_ms", Latency(answer_ms_)},
               {"published", publisher_->Counts()}};
  }

 private:
  static std::vector<std::unique_ptr<internal::MessageSink>> Sinks(std::shared_ptr<net::TopicPublisher> publisher) {
    std::vector<std::unique_ptr<internal::MessageSink>> sinks;
    sinks.push_back(internal::DdsSink(std::move(publisher), internal::Origin::kInput));
    return sinks;
  }
  static std::string Seconds(double t_s) { return std::to_string(t_s) + " s"; }

  static double MsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  // p50, p99 and max of wall-clock milliseconds (the report's; never a pass/fail figure).
  static nlohmann::json Latency(std::vector<double> ms) {
    std::sort(ms.begin(), ms.end());
    const auto q = [&](double p) {
      return ms.empty() ? 0.0 : ms[std::min(ms.size() - 1, static_cast<size_t>(p * ms.size()))];
    };
    return {{"count", ms.size()}, {"p50", q(0.5)}, {"p99", q(0.99)}, {"max", ms.empty() ? 0.0 : ms.back()}};
  }

  // Once the stack has every message before it: the step's question.
  void Ask(const ros::VehicleState& m) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!publisher_->WaitForAcks(std::chrono::duration_cast<std::chrono::milliseconds>(timeout_)))
      Alive("acknowledging the inputs before " + Seconds(m.time_s), std::chrono::steady_clock::now());
    acknowledged_ms_.push_back(MsSince(t0));
    publisher_->Publish(kVehicleStateTopic, ros::kVehicleStateType, m.header.stamp, ros::Encode(m));
  }
  void TakeTracks() {
    for (const auto& sample : tracks_.Take()) {
      const ros::Obstacles m = ros::DecodeObstacles(sample.cdr);
      on_tracks_(m.header.stamp, TracksFromRos(m));
    }
  }
  // Throws when the node ended, or `deadline` passed, while waiting for `what`.
  void Alive(const std::string& what, std::chrono::steady_clock::time_point deadline) {
    if (const auto code = child_->Poll())
      throw RuntimeError("the stack node " + Failed(*code) + " (waiting for " + what + ")");
    if (std::chrono::steady_clock::now() > deadline)
      throw RuntimeError("the stack node did not answer within " + std::to_string(node_.timeout_s) +
                         " s (node.command_timeout_s), waiting for " + what + "; its console: " + dir_ +
                         "/console.log");
  }
  std::string Failed(int code) const {
    return "ended with exit code " + std::to_string(code) + "; its console: " + dir_ + "/console.log";
  }

  const ClosedLoopConfig::StackNode& node_;
  std::chrono::steady_clock::duration timeout_;
  std::shared_ptr<net::Participant> participant_;
  std::shared_ptr<net::TopicPublisher> publisher_;
  internal::RosRecorder recorder_;
  net::Reader steps_, tracks_;
  OnTracks on_tracks_;
  std::string dir_;
  std::optional<ChildProcess> child_;
  // Wall clock per control step: until the stack acknowledged the step's inputs, and
  // from the question to the decision.
  std::vector<double> acknowledged_ms_, answer_ms_;
};

// A message from the car, for the stack node to handle in source-time order.
struct CarMessage {
  Stamp source_time;
  size_t topic;  // index into CarTopics()
  std::vector<uint8_t> cdr;
};

}  // namespace

namespace internal {

std::unique_ptr<StackLink> DdsStackLink(const sim::Scenario&, uint64_t seed, const ClosedLoopConfig& config,
                                        ClosedLoopResult&, StackLink::OnTracks on_tracks) {
  return std::make_unique<Dds>(seed, config, *config.stack_node, std::move(on_tracks));
}

}  // namespace internal

int RunStackNode(const params::Params& params, const StackNodeInputs& inputs, const std::string& out_dir, bool) {
  const sim::Scenario scenario = sim::LoadScenario(inputs.scenario);
  const uint64_t seed = inputs.seed.value_or(scenario.seed);
  ClosedLoopConfig config = LoopConfigFrom(params, scenario, inputs.map_dir);
  config.mcap = inputs.mcap;
  const std::vector<decide::Goal> mission = MissionOf(inputs.mission, scenario, config.car);
  const double timeout_s = params.Get<NodeOptions>("node").command_timeout_s;

  auto participant = NodeParticipant(params);
  std::vector<std::unique_ptr<net::Reader>> readers;
  net::WaitSet wait(*participant);
  for (const auto& [topic, type] : CarTopics()) {
    readers.push_back(
        std::make_unique<net::Reader>(*participant, topic, type, net::QosForTopic(topic, net::Qos::kKeepAll)));
    wait.Attach(*readers.back());
  }
  net::TopicPublisher publisher(participant, net::Qos::kKeepAll);
  // The car waits for this node's writers; this node for the car's readers of them.
  const auto wait_ms = std::chrono::milliseconds(static_cast<long>(1000 * timeout_s));
  publisher.WaitForReaders(kStepTopic, ros::kStackStepType, 1, wait_ms);
  publisher.WaitForReaders(kTracksTopic, ros::kObstaclesType, 1, wait_ms);

  ClosedLoopResult r;
  internal::LoopStack stack(scenario, seed, mission, config, Stamp{sim::Simulator::kEpochNs}, r);
  ros::RosObservations convert;
  std::vector<CarMessage> queued;
  long handled = 0;
  auto last_message = std::chrono::steady_clock::now();
  // Handles one car message; true at the end of the drive.
  const auto handle = [&](const CarMessage& m) {
    ++handled;
    const std::string& topic = CarTopics()[m.topic].first;
    if (topic == "/tf_static") {
      convert.AddStatic(ros::DecodeTfMessage(m.cdr));
    } else if (topic == "/scan") {
      const auto o = convert.Observe(ros::DecodeLaserScan(m.cdr), topic, 0, handled);
      stack.Observe(o.stamp, DriveSeconds(o.stamp), o.data);
    } else if (topic == "/odom") {
      const auto o = convert.Observe(ros::DecodeOdometry(m.cdr), topic, 0, handled);
      stack.Observe(o.stamp, DriveSeconds(o.stamp), o.data);
    } else if (topic == "/imu") {
      const ros::Imu imu = ros::DecodeImu(m.cdr);
      stack.Observe(imu.header.stamp, DriveSeconds(imu.header.stamp), ros::RosObservations::Imu(imu, topic));
    } else if (topic == kDetectionsTopic) {
      const ros::Obstacles d = ros::DecodeObstacles(m.cdr);
      std::vector<types::Obstacle> in_car;
      for (const auto& o : d.obstacles) in_car.push_back(FromRos(o, d.header.stamp));
      const auto tracks = stack.Detections(std::move(in_car), d.header.stamp);
      publisher.Publish(kTracksTopic, ros::kObstaclesType, d.header.stamp,
                        ros::Encode(TracksToRos(tracks, d.header.stamp)));
    } else {  // the vehicle state: a control step, or the end
      const ros::VehicleState v = ros::DecodeVehicleState(m.cdr);
      if (!v.stop.empty()) {
        if (v.stop != kEndOfDrive) stack.TimeLimit(v.time_s, v.stop);
        stack.Finish(v.header.stamp);
        return true;
      }
      const plan::Command c = stack.Control(v.time_s, v.header.stamp, v.speed_mps, v.steer_rad);
      const sim::Pose2 b = stack.Believed();
      publisher.Publish(kStepTopic, ros::kStackStepType, v.header.stamp,
                        ros::Encode(ros::StackStep{{v.header.stamp, "map"},
                                                   c.speed_mps,
                                                   c.steer_rad,
                                                   b.x,
                                                   b.y,
                                                   b.yaw_rad,
                                                   stack.state(),
                                                   stack.tracks_seen(),
                                                   stack.OnLocalPath(),
                                                   stack.Final()}));
      ros::AckermannDrive drive;
      drive.header = {v.header.stamp, "base_link"};
      drive.speed = static_cast<float>(c.speed_mps), drive.steering_angle = static_cast<float>(c.steer_rad);
      publisher.Publish("/drive", ros::kAckermannDriveType, v.header.stamp, ros::Encode(drive));
    }
    return false;
  };

  io::RunReport report("node stack");
  report.json()["inputs"] = {{"scenario", inputs.scenario},
                             {"seed", seed},
                             {"mission", inputs.mission.empty() ? "default" : inputs.mission},
                             {"map", inputs.map_dir},
                             {"domain", params.Get<net::Options>("dds").domain},
                             {"params_files", inputs.param_files},
                             {"overrides", inputs.overrides}};
  bool ended = false;
  std::string stopped;
  while (!ended) {
    if (InterruptRequested()) break;
    if (wait.Wait(std::chrono::milliseconds(50))) last_message = std::chrono::steady_clock::now();
    for (size_t k = 0; k < readers.size(); ++k)
      for (auto& sample : readers[k]->Take()) queued.push_back({sample.source_time, k, std::move(sample.cdr)});
    // Everything before a vehicle state has come (the car waited for the acknowledgements).
    std::stable_sort(queued.begin(), queued.end(),
                     [](const CarMessage& a, const CarMessage& b) { return a.source_time < b.source_time; });
    const auto question = std::find_if(queued.begin(), queued.end(), [](const CarMessage& m) {
      return CarTopics()[m.topic].first == kVehicleStateTopic;
    });
    if (question == queued.end()) {
      if (std::chrono::steady_clock::now() - last_message > std::chrono::duration<double>(timeout_s)) {
        stopped = "no message from the car for " + std::to_string(timeout_s) + " s (node.command_timeout_s)";
        break;
      }
      continue;
    }
    const auto upto = question + 1;
    for (auto it = queued.begin(); it != upto && !ended; ++it) ended = handle(*it);
    queued.erase(queued.begin(), upto);
  }
  if (!ended) stack.Finish(Stamp{sim::Simulator::kEpochNs});
  publisher.WaitForAcks(std::chrono::seconds(10));
  io::WriteTextAtomically(out_dir + "/stack.json", internal::StackFiguresToJson(r).dump());
  report.AddOutput("stack.json");
  if (r.drawn_map) {
    std::filesystem::create_directories(out_dir + "/map");
    WriteMapArtefact(*r.drawn_map, out_dir + "/map");
    report.AddOutput("map/");
  }
  report.json()["counts"] = {{"messages", handled}, {"published", publisher.Counts()}};
  int exit_code = 0;
  if (InterruptRequested()) {
    report.SetInterrupted(std::to_string(handled) + " messages");
    exit_code = InterruptExitCode();
  } else if (!stopped.empty()) {
    report.SetIncomplete(stopped);
    spdlog::error("node stack: {}", stopped);
    exit_code = 1;
  }
  report.Write(out_dir);
  return exit_code;
}

}  // namespace specht::pipeline
