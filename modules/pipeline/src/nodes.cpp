#include "specht/pipeline/nodes.h"

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <chrono>
#include <filesystem>

#include "internal/dataset_drive.h"
#include "internal/ros_recorder.h"
#include "specht/core/interrupt.h"
#include "specht/core/log.h"
#include "specht/core/progress.h"
#include "specht/io/data_dir.h"
#include "specht/io/report.h"
#include "specht/io/ros_messages.h"
#include "specht/net/topics.h"
#include "specht/pipeline/replay.h"
#include "specht/slam/scan_matching.h"

namespace specht::pipeline {

std::shared_ptr<net::Participant> NodeParticipant(const params::Params& params) {
  return std::make_shared<net::Participant>(params.Get<net::Options>("dds"));
}

int PlayDataset(const params::Params& params, const PlayInputs& inputs, const std::string& out_dir, bool quiet) {
  const std::string dataset = inputs.dataset.empty() ? io::DefaultRawlog() : inputs.dataset;
  const auto& replay = params.Get<io::ReplayOptions>("replay");
  const auto& node = params.Get<NodeOptions>("node");
  auto source = OpenDatasetSource(dataset, replay);
  auto publisher = std::make_shared<net::TopicPublisher>(NodeParticipant(params), net::Qos::kKeepAll);
  std::vector<std::unique_ptr<internal::MessageSink>> sinks;
  sinks.push_back(internal::DdsSink(publisher, internal::Origin::kInput));
  internal::RosRecorder recorder(std::move(sinks), 0, params.Get<slam::GridOptions>("grid"));

  io::RunReport report("node play");
  auto& j = report.json();
  j["inputs"] = {{"dataset", dataset},
                 {"format", source->Format()},
                 {"domain", params.Get<net::Options>("dds").domain},
                 {"params_files", inputs.param_files},
                 {"overrides", inputs.overrides}};
  // Every writer before the wait, so that the subscribers match them all while the
  // player waits for its scans' subscribers; then a moment more for as many readers
  // of the odometry (a subscriber may read none).
  for (const auto& [topic, type] : {std::pair{"/odom", io::ros::kOdometryType},
                                    {"/tf", io::ros::kTfMessageType},
                                    {"/tf_static", io::ros::kTfMessageType},
                                    {"/imu", io::ros::kImuType},
                                    {"/clock", io::ros::kClockType}})
    publisher->Advertise(topic, type);
  const auto wait = std::chrono::duration<double>(node.wait_for_subscriber_s);
  if (!publisher->WaitForReaders(node.scan_topic, io::ros::kLaserScanType, node.subscribers,
                                 std::chrono::duration_cast<std::chrono::milliseconds>(wait)))
    spdlog::warn("node play: fewer than {} subscribers to {} after {:.0f} s; publishing anyway", node.subscribers,
                 node.scan_topic, node.wait_for_subscriber_s);
  else
    publisher->WaitForReaders("/odom", io::ros::kOdometryType, node.subscribers, std::chrono::seconds(2));
  io::ReplayClock clock(replay);
  io::StageTimer timer;
  int exit_code = 0;
  long scans = 0;
  const internal::DriveResult run = internal::Drive(
      *source, clock,
      [&](Stamp t, const mrpt::obs::CObservation::Ptr& o) {
        auto timing = timer.Time("publish");
        recorder.Observation(t, o);
        publisher->Publish("/clock", io::ros::kClockType, t, io::ros::EncodeClock(t));  // use_sim_time
        if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) ++scans;
        return std::make_pair(scans, std::string());
      },
      timer, report, quiet, exit_code);
  publisher->WaitForAcks(std::chrono::seconds(10));  // the subscribers have everything before the writers go
  if (scans == 0 && exit_code == 0) throw InputError(dataset + ": no laser scan to publish");
  const double data_s = run.first ? SecondsBetween(*run.first, *run.last) : 0.0;
  j["counts"]["published"] = publisher->Counts();
  j["input_notes"] = source->Notes();
  j["timing"] = {{"wall_s", run.wall_s},
                 {"data_s", data_s},
                 {"real_time_factor", run.wall_s > 0 ? data_s / run.wall_s : 0.0},
                 {"stages", timer.ToJson()}};
  report.Write(out_dir);
  spdlog::info("node play: {} scans in {:.1f} s of data, {:.1f} s", scans, data_s, run.wall_s);
  return exit_code;
}

int RecordTopics(const params::Params& params, const RecordInputs& inputs, const std::string& out_dir, bool quiet) {
  const auto& node = params.Get<NodeOptions>("node");
  const std::string path = internal::RecordingPath(out_dir, inputs.mcap);
  const std::vector<net::TopicSpec> topics = {
      {node.scan_topic, io::ros::kLaserScanType, true},
      {node.odometry_topic, io::ros::kOdometryType, true},
      {"/tf", io::ros::kTfMessageType, false},
      {"/tf_static", io::ros::kTfMessageType, false},
      {"/map", io::ros::kOccupancyGridType, false},
      {"/trajectory", io::ros::kPathType, false},
      {"/path", io::ros::kPathType, false},
      {"/tracks", io::ros::kPoseArrayType, false},
  };
  net::TopicMerger merger(NodeParticipant(params), topics, node.settle_s, node.idle_end_s);
  io::RunReport report("node record");
  auto& j = report.json();
  j["inputs"] = {{"domain", params.Get<net::Options>("dds").domain},
                 {"params_files", inputs.param_files},
                 {"overrides", inputs.overrides}};
  auto sink = internal::McapSink(path);
  std::map<std::string, uint64_t> counts;
  ProgressLine progress("node record", "messages", !quiet);
  const auto wall0 = std::chrono::steady_clock::now();
  long messages = 0;
  while (auto m = merger.Next()) {
    sink->Write(m->topic, m->type, internal::Origin::kInput, m->sample.source_time, m->sample.cdr);
    ++counts[m->topic];
    progress.Update(static_cast<double>(++messages), -1, m->topic);
  }
  progress.Finish();
  sink->Close();
  int exit_code = 0;
  if (InterruptRequested()) {
    report.SetInterrupted(std::to_string(messages) + " messages");
    exit_code = InterruptExitCode();
  } else if (messages == 0) {
    std::filesystem::remove(path);  // no empty recording left behind as a result
    throw InputError("node record: no message on any topic");
  }
  j["counts"]["recorded"] = counts;
  j["input_figures"] = merger.Figures();
  j["timing"]["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  report.AddOutput(inputs.mcap);
  report.Write(out_dir);
  spdlog::info("node record: {} messages into {}", messages, path);
  return exit_code;
}

}  // namespace specht::pipeline
