// `specht node sim` (pipeline/nodes.h): the simulated car on DDS, sensors out,
// drive commands in.
#include <chrono>
#include <cmath>
#include <thread>

#include "internal/ros_recorder.h"
#include "specht/core/interrupt.h"
#include "specht/core/log.h"
#include "specht/core/progress.h"
#include "specht/io/replay.h"
#include "specht/io/report.h"
#include "specht/io/ros_conversion.h"
#include "specht/io/ros_messages.h"
#include "specht/io/trajectory_io.h"
#include "specht/net/topics.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/pipeline/nodes.h"
#include "specht/plan/car.h"

namespace specht::pipeline {
namespace {

mrpt::poses::CPose3D Pose3(const sim::Pose2& p) { return {p.x, p.y, 0, p.yaw_rad, 0, 0}; }

// The drive commands of node.command_topic, as the simulator takes them.
class DriveCommands {
 public:
  DriveCommands(net::Participant& participant, const std::string& topic, double max_steer_rate_rad_s)
      : reader_(participant, topic, io::ros::kAckermannDriveType, net::Qos::kKeepAll),
        max_steer_rate_rad_s_(max_steer_rate_rad_s) {}

  // The newest command stamped at or after `t` (lockstep: the one for this step), or
  // the newest at all (free running); nullopt when none came.
  std::optional<sim::Simulator::EgoCommand> Take(Stamp t, bool at_or_after_t) {
    for (const auto& sample : reader_.Take()) {
      const auto m = io::ros::DecodeAckermannDrive(sample.cdr);
      ++received_;
      if (!at_or_after_t || m.header.stamp >= t)
        pending_ = EgoCommandOf(m.speed, m.steering_angle, m.steering_angle_velocity, max_steer_rate_rad_s_);
    }
    auto command = pending_;
    if (at_or_after_t) pending_.reset();
    return command;
  }
  bool Wait(std::chrono::milliseconds timeout) const { return reader_.WaitForData(timeout); }
  long received() const { return received_; }

 private:
  net::Reader reader_;
  double max_steer_rate_rad_s_;
  std::optional<sim::Simulator::EgoCommand> pending_;
  long received_ = 0;
};

}  // namespace

sim::Simulator::EgoCommand EgoCommandOf(float speed_mps, float steer_rad, float steer_rate_rad_s,
                                        double max_steer_rate_rad_s) {
  const double rate =
      steer_rate_rad_s > 0 ? std::min<double>(steer_rate_rad_s, max_steer_rate_rad_s) : max_steer_rate_rad_s;
  return {speed_mps, steer_rad, rate};
}

Trajectory DriveSimulatedCar(sim::Simulator& sim, double duration_s, double control_hz, const CommandAt& command,
                             const sim::Simulator::Sink& observe) {
  const int substeps = std::max(1, static_cast<int>(std::lround(1.0 / (control_hz * sim::Simulator::kStepS))));
  Trajectory truth;
  while (sim.time_s() < duration_s - 1e-9 && !InterruptRequested()) {
    const auto c = command(sim.stamp(), sim);
    if (!c) break;
    sim.CommandEgo(*c);
    truth.push_back({sim.stamp(), Pose3(sim.ego().pose)});
    for (int k = 0; k < substeps; ++k) sim.Step(observe);
  }
  truth.push_back({sim.stamp(), Pose3(sim.ego().pose)});
  return truth;
}

int RunSimulatorNode(const params::Params& params, const SimNodeInputs& inputs, const std::string& out_dir,
                     bool quiet) {
  const sim::Scenario scenario = sim::LoadScenario(inputs.scenario);
  const uint64_t seed = inputs.seed.value_or(scenario.seed);
  const double duration_s = inputs.duration_s.value_or(scenario.duration_s);
  const auto& node = params.Get<NodeOptions>("node");
  const auto& replay = params.Get<io::ReplayOptions>("replay");
  const double control_hz = params.Get<ClosedLoopOptions>("closed_loop").control_hz;
  const plan::CarOptions car = ScenarioCar(scenario, params.Get<plan::CarOptions>("car"));
  auto participant = NodeParticipant(params);
  auto publisher = std::make_shared<net::TopicPublisher>(participant, net::Qos::kKeepAll);
  std::vector<std::unique_ptr<internal::MessageSink>> sinks;
  sinks.push_back(internal::DdsSink(publisher, internal::Origin::kInput));
  internal::RosRecorder recorder(std::move(sinks), 0, params.Get<slam::GridOptions>("grid"));
  DriveCommands commands(*participant, node.command_topic, car.max_steer_rate_deg_s * M_PI / 180);

  const auto publish_clock = [&](const sim::Simulator& sim) {
    publisher->Publish("/clock", io::ros::kClockType, sim.stamp(), io::ros::EncodeClock(sim.stamp()));
  };
  const auto publish_truth = [&](const sim::Simulator& sim) {
    io::ros::Odometry truth;
    truth.header = {sim.stamp(), "map"};
    truth.child_frame_id = "base_link";
    truth.pose = io::ros::FromMrpt(Pose3(sim.ego().pose));
    truth.vx = sim.ego().speed_mps;
    truth.wz = sim.ego().yaw_rate;
    publisher->Publish("/ground_truth", io::ros::kOdometryType, sim.stamp(), io::ros::Encode(truth));
  };
  // Lockstep: every reader has the sensor messages up to now before the clock says
  // so; then the step waits for its command, repeating /clock (a best-effort topic)
  // after every 100 ms without one.
  std::string stopped;  // why the drive ended before its duration
  io::StageTimer timer;
  const auto lockstep_command = [&](Stamp t, const sim::Simulator& sim) -> std::optional<sim::Simulator::EgoCommand> {
    {
      auto timing = timer.Time("sensors_acknowledged");
      publisher->WaitForAcks(std::chrono::milliseconds(static_cast<long>(1000 * node.command_timeout_s)));
    }
    auto timing = timer.Time("command_wait");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(node.command_timeout_s);
    publish_truth(sim);
    publish_clock(sim);
    for (;;) {
      if (auto c = commands.Take(t, true)) return c;
      if (InterruptRequested()) return std::nullopt;
      if (std::chrono::steady_clock::now() > deadline) {
        stopped = "no command on " + node.command_topic + " for " + std::to_string(node.command_timeout_s) +
                  " s at t = " + std::to_string(sim.time_s()) + " s";
        return std::nullopt;
      }
      if (!commands.Wait(std::chrono::milliseconds(100))) publish_clock(sim);  // once more: /clock is best effort
    }
  };
  sim::Simulator::EgoCommand latest;  // free running: standing still until told otherwise
  io::ReplayClock pace(replay);
  const auto free_command = [&](Stamp t, const sim::Simulator& sim) -> std::optional<sim::Simulator::EgoCommand> {
    pace.WaitFor(t);
    publish_truth(sim);
    publish_clock(sim);
    if (auto c = commands.Take(t, false)) latest = *c;
    return latest;
  };

  io::RunReport report("node sim");
  auto& j = report.json();
  j["inputs"] = {{"scenario", inputs.scenario},
                 {"seed", seed},
                 {"duration_s", duration_s},
                 {"lockstep", node.lockstep},
                 {"domain", params.Get<net::Options>("dds").domain},
                 {"params_files", inputs.param_files},
                 {"overrides", inputs.overrides}};
  sim::Simulator sim(scenario, seed);
  ProgressLine progress("node sim", "s", !quiet);
  const auto wall0 = std::chrono::steady_clock::now();
  long observations = 0;
  const Trajectory truth = DriveSimulatedCar(sim, duration_s, control_hz,
                                             node.lockstep ? CommandAt(lockstep_command) : CommandAt(free_command),
                                             [&](Stamp t, const mrpt::obs::CObservation::Ptr& o) {
                                               recorder.Observation(t, o);
                                               if (++observations % 100 == 0)
                                                 progress.Update(sim.time_s(), sim.time_s() / duration_s);
                                             });
  progress.Finish();
  publisher->WaitForAcks(std::chrono::seconds(10));
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  io::WriteTum(truth, out_dir + "/ground_truth.tum");
  report.AddOutput("ground_truth.tum");
  const int exit_code = report.Ended(std::to_string(sim.time_s()) + " s simulated", stopped);
  j["counts"] = {{"published", publisher->Counts()},
                 {"commands", commands.received()},
                 {"control_steps", static_cast<long>(truth.size()) - 1}};
  j["timing"] = {{"wall_s", wall_s},
                 {"data_s", sim.time_s()},
                 {"real_time_factor", sim.time_s() / wall_s},
                 {"stages", timer.ToJson()}};
  report.Write(out_dir);
  spdlog::info("node sim: {:.1f} s simulated in {:.1f} s, {} commands", sim.time_s(), wall_s, commands.received());
  return exit_code;
}

}  // namespace specht::pipeline
