#include "specht/pipeline/nodes.h"

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <chrono>

#include "internal/dataset_drive.h"
#include "internal/ros_recorder.h"
#include "specht/core/log.h"
#include "specht/io/data_dir.h"
#include "specht/io/report.h"
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
  const auto wait = std::chrono::duration<double>(node.wait_for_subscriber_s);
  if (!publisher->WaitForReaders(node.scan_topic, "sensor_msgs/msg/LaserScan", 1,
                                 std::chrono::duration_cast<std::chrono::milliseconds>(wait)))
    spdlog::warn("node play: no subscriber to {} after {:.0f} s; publishing anyway", node.scan_topic,
                 node.wait_for_subscriber_s);
  io::ReplayClock clock(replay);
  io::StageTimer timer;
  int exit_code = 0;
  long scans = 0;
  const internal::DriveResult run = internal::Drive(
      *source, clock,
      [&](Stamp t, const mrpt::obs::CObservation::Ptr& o) {
        auto timing = timer.Time("publish");
        recorder.Observation(t, o);
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

}  // namespace specht::pipeline
