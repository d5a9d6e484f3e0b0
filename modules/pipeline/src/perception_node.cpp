// `specht node perception` (nodes.h): the closed loop's tracker as a node of its own.
// Each detector frame on /detections (the car's frame) is placed at the pose the
// stack published for it on /localization/odometry (the same stamp), tracked, and
// answered on /perception/tracks and /perception/obstacles (internal/
// perception_messages.h). Frames are tracked in stamp order; a frame whose pose never
// came is skipped once a later frame is complete (it cannot be tracked out of order).
#include <algorithm>
#include <chrono>
#include <map>

#include "internal/loop_perception.h"
#include "internal/perception_messages.h"
#include "specht/core/interrupt.h"
#include "specht/core/log.h"
#include "specht/io/report.h"
#include "specht/net/topics.h"
#include "specht/pipeline/nodes.h"
#include "specht/track/tracker.h"

namespace specht::pipeline {
namespace {

namespace ros = io::ros;
using internal::kDetectionsTopic, internal::kLocalizationTopic, internal::kObstaclesTopic, internal::kTracksTopic,
    internal::kVehicleStateTopic;

// A frame's two halves: the car's detections and the stack's pose for them.
struct Pending {
  std::optional<ros::Obstacles> detections;
  std::optional<sim::Pose2> believed;
};

}  // namespace

int RunPerceptionNode(const params::Params& params, const PerceptionNodeInputs& inputs, const std::string& out_dir,
                      bool) {
  const double timeout_s = params.Get<NodeOptions>("node").command_timeout_s;
  auto participant = NodeParticipant(params);
  net::Reader detections(*participant, kDetectionsTopic, ros::kObstaclesType, net::Qos::kKeepAll);
  net::Reader poses(*participant, kLocalizationTopic, ros::kOdometryType, net::Qos::kKeepAll);
  net::Reader vehicle(*participant, kVehicleStateTopic, ros::kVehicleStateType, net::Qos::kKeepAll);
  net::WaitSet wait(*participant);
  for (const net::Reader* r : {&detections, &poses, &vehicle}) wait.Attach(*r);
  net::TopicPublisher publisher(participant, net::Qos::kKeepAll);
  publisher.Advertise(kTracksTopic, ros::kTracksType);
  publisher.Advertise(kObstaclesTopic, ros::kObstaclesType);

  track::Tracker tracker(params.Get<track::TrackerOptions>("track"));
  std::map<Stamp, Pending> pending;
  Stamp last{-1};
  long frames = 0, detected = 0, skipped = 0;
  // Tracks every complete frame, oldest first; what is older than a tracked one is dropped.
  const auto track_complete = [&] {
    for (auto it = pending.begin(); it != pending.end();) {
      if (!it->second.detections || !it->second.believed) {
        ++it;
        continue;
      }
      for (auto old = pending.begin(); old != it; ++old) skipped += old->second.detections ? 1 : 0;
      const Stamp stamp = it->first;
      auto obstacles = internal::PlacedAt(internal::ObstaclesFromRos(*it->second.detections), *it->second.believed);
      tracker.Update(obstacles, stamp);
      publisher.Publish(kObstaclesTopic, ros::kObstaclesType, stamp,
                        ros::Encode(internal::ObstaclesToRos(obstacles, stamp, "map")));
      publisher.Publish(kTracksTopic, ros::kTracksType, stamp,
                        ros::Encode(internal::TracksToRos(tracker.Tracks(), stamp)));
      ++frames, detected += static_cast<long>(obstacles.size()), last = stamp;
      it = pending.erase(pending.begin(), std::next(it));
    }
  };

  io::RunReport report("node perception");
  report.json()["inputs"] = {{"domain", params.Get<net::Options>("dds").domain},
                             {"params_files", inputs.param_files},
                             {"overrides", inputs.overrides}};
  std::string stopped;
  std::optional<Stamp> end;  // the drive ended here: the frames before it are still answered
  auto last_message = std::chrono::steady_clock::now();
  const auto silence = std::chrono::duration<double>(timeout_s);
  const auto done = [&] {
    return end && std::none_of(pending.begin(), pending.end(), [&](const auto& p) {
             return p.first <= *end && p.second.detections && !p.second.believed;
           });
  };
  while (!done() && !InterruptRequested()) {
    if (wait.Wait(std::chrono::milliseconds(50))) last_message = std::chrono::steady_clock::now();
    // The end first: the run publishes it only once every reader has acknowledged the
    // detections before it, so the takes below see them all. Taken last, a frame
    // arriving between the two takes was missed (its end seen, the loop ended).
    for (auto& s : vehicle.Take())
      if (const auto v = ros::DecodeVehicleState(s.cdr); !v.stop.empty()) end = v.header.stamp;
    for (auto& s : detections.Take()) {
      ros::Obstacles m = ros::DecodeObstacles(s.cdr);
      if (m.header.stamp > last) pending[m.header.stamp].detections = std::move(m);
    }
    for (auto& s : poses.Take()) {
      const ros::Odometry m = ros::DecodeOdometry(s.cdr);
      if (m.header.stamp > last) pending[m.header.stamp].believed = internal::PoseFromRos(m);
    }
    track_complete();
    // Silence ends the node; after the drive's end, a frame whose pose does not come.
    if (std::chrono::steady_clock::now() - last_message > silence) {
      if (!end) stopped = "no message for " + std::to_string(timeout_s) + " s (node.command_timeout_s)";
      break;
    }
  }
  publisher.WaitForAcks(std::chrono::seconds(10));
  report.json()["counts"] = {
      {"frames", frames}, {"detections", detected}, {"skipped", skipped}, {"published", publisher.Counts()}};
  const int exit_code = report.Ended(std::to_string(frames) + " frames", stopped);
  report.Write(out_dir);
  return exit_code;
}

}  // namespace specht::pipeline
