// The closed loop's stack over DDS: `specht node stack` (nodes.h) and the car side's
// link to it (internal/stack_link.h), which `specht run --nodes` uses. One file owns
// the protocol:
//   car → stack  /scan, /odom, /imu, /tf, /tf_static (internal/ros_recorder.h),
//                /detections (specht_msgs/Obstacles, the car's frame) and
//                /vehicle_state (specht_msgs/VehicleState: a control step, or with
//                `stop` the end of the drive)
//   stack → car  /stack/step (specht_msgs/StackStep: the decision), /perception/tracks
//                (specht_msgs/Tracks, map frame: the tracks of each detector frame,
//                for the referee) and /drive (ackermann_msgs/AckermannDriveStamped:
//                the command as ROS tools read it, float32)
// With a perception node (perception_node.cpp) the tracks come from it: the stack
// answers each detector frame with its pose on /localization/odometry and takes the
// node's /perception/tracks and /perception/obstacles for it (internal/
// perception_messages.h). The car starts the perception node and restarts it when it
// dies, as a launch file's respawn would.
// Lockstep: the car publishes a step's inputs, waits until the stack has acknowledged
// them, then asks for the step's decision. Every car message comes from one
// publisher, whose source times increase in publication order (net/topics.h): the
// stack handles them sorted by source time, which is the order the in-process loop
// hands them over.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <thread>

#include "internal/perception_messages.h"
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

constexpr char kStepTopic[] = "/stack/step";
using internal::kDetectionsTopic, internal::kEndOfDrive, internal::kLocalizationTopic, internal::kObstaclesTopic,
    internal::kTracksTopic, internal::kVehicleStateTopic;
// The car's topics, as the stack reads them.
const std::vector<std::pair<std::string, std::string>>& CarTopics() {
  static const std::vector<std::pair<std::string, std::string>> topics = {
      {"/tf_static", ros::kTfMessageType},     {"/scan", ros::kLaserScanType},
      {"/odom", ros::kOdometryType},           {"/imu", ros::kImuType},
      {kDetectionsTopic, ros::kObstaclesType}, {kVehicleStateTopic, ros::kVehicleStateType}};  // questions last
  return topics;
}

// The car side's link: publishes what the car delivers, waits for the stack node's
// decisions; the node runs as a child process for one drive.
class NodeStackLink : public internal::StackLink {
 public:
  NodeStackLink(uint64_t seed, const ClosedLoopConfig& config, const ClosedLoopConfig::StackNode& node,
                OnTracks on_tracks)
      : node_(node),
        timeout_(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(node.timeout_s))),
        participant_(std::make_shared<net::Participant>(node.dds)),
        publisher_(std::make_shared<net::TopicPublisher>(participant_, net::Qos::kKeepAll)),
        recorder_(Sinks(publisher_), 0, config.slam.grid),
        steps_(*participant_, kStepTopic, ros::kStackStepType, net::Qos::kKeepAll),
        tracks_(*participant_, kTracksTopic, ros::kTracksType, net::Qos::kKeepAll),
        on_tracks_(std::move(on_tracks)),
        dir_(node.out_dir + "/stack-" + std::to_string(seed)),
        perception_dir_(node.out_dir + "/perception-" + std::to_string(seed)) {
    std::filesystem::create_directories(dir_);
    std::vector<std::string> argv = node.command;
    argv.insert(argv.end(), {"--seed", std::to_string(seed), "-o", dir_});
    if (!config.mcap.empty()) argv.insert(argv.end(), {"--mcap", std::filesystem::absolute(config.mcap).string()});
    child_.emplace(argv, dir_ + "/console.log");
    if (!node.perception_command.empty()) StartPerception();
    // Started when it reads every topic the car publishes and answers on both of its
    // own; the perception node reads the detections and the vehicle state too.
    const auto deadline = std::chrono::steady_clock::now() + timeout_;
    for (const auto& [topic, type] : CarTopics()) {
      const bool perceived = perception_ && (topic == kDetectionsTopic || topic == kVehicleStateTopic);
      while (!publisher_->WaitForReaders(topic, type, perceived ? 2 : 1, std::chrono::milliseconds(100)))
        Starting("a reader of " + topic, deadline);
    }
    while (!steps_.WaitForWriters(1, std::chrono::milliseconds(100)) ||
           !tracks_.WaitForWriters(1, std::chrono::milliseconds(100)))
      Starting("start", deadline);
  }

  void Observe(Stamp t, double, const mrpt::obs::CObservation::Ptr& observation) override {
    recorder_.Observation(t, observation);
  }

  void Detections(std::vector<types::Obstacle> in_car, Stamp stamp) override {
    publisher_->Publish(kDetectionsTopic, ros::kObstaclesType, stamp,
                        ros::Encode(internal::ObstaclesToRos(in_car, stamp, "base_link")));
  }

  // The oracle reads the simulator, which stays with the car: refused before the drive
  // (mission_runs.cpp), and ignored here as the full stack ignores it.
  void OracleEgo(const sim::Pose2&) override {}
  void OracleAgents(const std::vector<sim::AgentTruth>&, Stamp) override {
    throw RuntimeError("the truth stack's perception oracle does not run over --nodes");
  }

  internal::StackDecision Control(double t_s, Stamp stamp, double speed_mps, double steer_rad) override {
    if (perception_) RespawnPerceptionIfGone(t_s);
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
    nlohmann::json perception;
    if (perception_) {
      perception = {{"node", std::filesystem::path(perception_dir_).filename().string()},
                    {"exit_code", perception_->WaitOrKill(node_.timeout_s)},
                    {"restarts", perception_restarts_}};
    }
    std::ifstream in(dir_ + "/stack.json");
    internal::StackFiguresFromJson(nlohmann::json::parse(in), r);
    if (std::filesystem::exists(dir_ + "/map"))
      r.drawn_map = std::make_shared<MapArtefact>(ReadMapArtefact(dir_ + "/map"));
    r.nodes = {{"stack_node", std::filesystem::path(dir_).filename().string()},
               {"domain", node_.dds.domain},
               {"acknowledged_ms", io::Quantiles(acknowledged_ms_, {0.5, 0.99})},
               {"answer_ms", io::Quantiles(answer_ms_, {0.5, 0.99})},
               {"published", publisher_->Counts()}};
    if (perception_) r.nodes["perception_node"] = perception;
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
      const ros::Tracks m = ros::DecodeTracks(sample.cdr);
      on_tracks_(m.header.stamp, internal::TracksFromRos(m));
    }
  }
  void StartPerception() {
    std::filesystem::create_directories(perception_dir_);
    std::vector<std::string> argv = node_.perception_command;
    argv.insert(argv.end(), {"-o", perception_dir_});
    perception_.emplace(argv, perception_dir_ + "/console.log");
  }
  // A perception node that ended is started again at once (its tracks of the frames
  // in between are missing: the stack's perception timeout decides what the car does).
  void RespawnPerceptionIfGone(double t_s) {
    const auto code = perception_->Poll();
    if (!code) return;
    spdlog::warn("run: the perception node ended with exit code {} at {:.2f} s into the drive; restarting it", *code,
                 t_s);
    perception_restarts_.push_back({{"gone_at_s", t_s}, {"exit_code", *code}});
    StartPerception();
  }
  // As Alive, and a perception node that ended before the drive began ends the run
  // too (during the drive one is restarted instead).
  void Starting(const std::string& what, std::chrono::steady_clock::time_point deadline) {
    if (perception_)
      if (const auto code = perception_->Poll())
        throw RuntimeError("the perception node ended with exit code " + std::to_string(*code) + " (waiting for " +
                           what + "); its console: " + perception_dir_ + "/console.log");
    Alive(what, deadline);
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
  std::string dir_, perception_dir_;
  std::optional<ChildProcess> child_, perception_;
  nlohmann::json perception_restarts_ = nlohmann::json::array();
  // Wall clock per control step: until the stack acknowledged the step's inputs, and
  // from the question to the decision.
  std::vector<double> acknowledged_ms_, answer_ms_;
};

// The stack node's side of a perception node: for each detector frame, the pose it
// is placed at goes out and the frame's tracks and obstacles come back.
class RemotePerception {
 public:
  struct Frame {
    std::vector<types::Track> tracks;
    std::vector<types::Obstacle> obstacles;
  };
  RemotePerception(net::Participant& participant, net::TopicPublisher& publisher, double wait_s)
      : publisher_(publisher),
        wait_(std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(wait_s))),
        tracks_(participant, kTracksTopic, ros::kTracksType, net::Qos::kKeepAll),
        obstacles_(participant, kObstaclesTopic, ros::kObstaclesType, net::Qos::kKeepAll) {
    publisher_.Advertise(kLocalizationTopic, ros::kOdometryType);
  }
  // Until the perception node is there to answer the first frame.
  void WaitForNode(std::chrono::milliseconds timeout) {
    publisher_.WaitForReaders(kLocalizationTopic, ros::kOdometryType, 1, timeout);
    tracks_.WaitForWriters(1, timeout);
    obstacles_.WaitForWriters(1, timeout);
  }
  // The perception node's answer to the detector frame at `stamp`, placed at
  // `believed`; none when no node is there or it did not answer in time.
  std::optional<Frame> Ask(Stamp stamp, const sim::Pose2& believed) {
    publisher_.Publish(kLocalizationTopic, ros::kOdometryType, stamp,
                       ros::Encode(internal::PoseToRos(believed, stamp)));
    const auto asked = std::chrono::steady_clock::now();
    const auto deadline = asked + wait_;
    for (;;) {
      for (const auto& sample : tracks_.Take())
        if (ros::Tracks m = ros::DecodeTracks(sample.cdr); m.header.stamp >= stamp)
          tracks_at_[m.header.stamp] = internal::TracksFromRos(m);
      for (const auto& sample : obstacles_.Take())
        if (ros::Obstacles m = ros::DecodeObstacles(sample.cdr); m.header.stamp >= stamp)
          obstacles_at_[m.header.stamp] = internal::ObstaclesFromRos(m);
      tracks_at_.erase(tracks_at_.begin(), tracks_at_.lower_bound(stamp));
      obstacles_at_.erase(obstacles_at_.begin(), obstacles_at_.lower_bound(stamp));
      const auto t = tracks_at_.find(stamp);
      const auto o = obstacles_at_.find(stamp);
      if (t != tracks_at_.end() && o != obstacles_at_.end()) {
        Frame frame{std::move(t->second), std::move(o->second)};
        tracks_at_.erase(t), obstacles_at_.erase(o);
        ++answered_, warned_ = false;
        answer_ms_.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - asked).count());
        return frame;
      }
      if (tracks_.MatchedWriters() == 0 || std::chrono::steady_clock::now() > deadline) break;
      tracks_.WaitForData(std::chrono::milliseconds(2));
    }
    ++missing_;
    if (!warned_)  // once a gap: the first frame missing after one answered
      spdlog::warn("node stack: no tracks from the perception node for the frame at {} s", stamp.Seconds());
    warned_ = true;
    return std::nullopt;
  }
  // Frames answered and missing, and the wall-clock milliseconds from a frame's pose
  // sent to its tracks back (the report's; never a pass/fail figure).
  nlohmann::json ToJson() const {
    return {{"answered", answered_}, {"missing", missing_}, {"answer_ms", io::Quantiles(answer_ms_, {0.5, 0.99})}};
  }

 private:
  net::TopicPublisher& publisher_;
  std::chrono::steady_clock::duration wait_;
  net::Reader tracks_, obstacles_;
  std::map<Stamp, std::vector<types::Track>> tracks_at_;
  std::map<Stamp, std::vector<types::Obstacle>> obstacles_at_;
  long answered_ = 0, missing_ = 0;
  bool warned_ = false;  // of the current gap
  std::vector<double> answer_ms_;
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
  return std::make_unique<NodeStackLink>(seed, config, *config.stack_node, std::move(on_tracks));
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
  std::optional<RemotePerception> remote;
  if (inputs.perception_node)
    remote.emplace(*participant, publisher, params.Get<NodeOptions>("node").perception_wait_s);
  // The car waits for this node's writers; this node for the car's readers of them.
  const auto wait_ms = std::chrono::milliseconds(static_cast<long>(1000 * timeout_s));
  publisher.WaitForReaders(kStepTopic, ros::kStackStepType, 1, wait_ms);
  if (remote)
    remote->WaitForNode(wait_ms);
  else
    publisher.WaitForReaders(kTracksTopic, ros::kTracksType, 1, wait_ms);

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
      stack.Observe(o.stamp, sim::Simulator::SecondsAt(o.stamp), o.data);
    } else if (topic == "/odom") {
      const auto o = convert.Observe(ros::DecodeOdometry(m.cdr), topic, 0, handled);
      stack.Observe(o.stamp, sim::Simulator::SecondsAt(o.stamp), o.data);
    } else if (topic == "/imu") {
      const ros::Imu imu = ros::DecodeImu(m.cdr);
      stack.Observe(imu.header.stamp, sim::Simulator::SecondsAt(imu.header.stamp),
                    ros::RosObservations::Imu(imu, topic));
    } else if (topic == kDetectionsTopic) {
      const ros::Obstacles d = ros::DecodeObstacles(m.cdr);
      if (remote) {
        if (auto frame = remote->Ask(d.header.stamp, stack.Localized()))
          stack.Tracked(std::move(frame->tracks), std::move(frame->obstacles), d.header.stamp);
      } else {
        const auto tracks = stack.Detections(internal::ObstaclesFromRos(d), d.header.stamp);
        publisher.Publish(kTracksTopic, ros::kTracksType, d.header.stamp,
                          ros::Encode(internal::TracksToRos(tracks, d.header.stamp)));
      }
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
  const size_t questions = readers.size() - 1;  // the vehicle state, last in CarTopics()
  while (!ended) {
    if (InterruptRequested()) break;
    if (wait.Wait(std::chrono::milliseconds(50))) last_message = std::chrono::steady_clock::now();
    // The questions are taken first and queued last. The car publishes one only once
    // every reader has acknowledged the messages before it, so the takes after it see
    // all of them (taken last, a message arriving between two takes came after its
    // question, and the drive diverged); queued last, a question stays behind the
    // inputs of its own time in the stable sort.
    auto asked = readers[questions]->Take();
    for (size_t k = 0; k < questions; ++k)
      for (auto& sample : readers[k]->Take()) queued.push_back({sample.source_time, k, std::move(sample.cdr)});
    for (auto& sample : asked) queued.push_back({sample.source_time, questions, std::move(sample.cdr)});
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
  if (remote) report.json()["perception_node"] = remote->ToJson();
  const int exit_code = report.Ended(std::to_string(handled) + " messages", stopped);
  report.Write(out_dir);
  return exit_code;
}

}  // namespace specht::pipeline
