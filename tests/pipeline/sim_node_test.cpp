// The simulator node (pipeline/nodes.h) in lockstep: a commander in this process
// drives the car over DDS, steering by the odometry the node published, and the
// drive equals the one the same commander gives the simulator in-process — pose for
// pose, every run. That holds only when every command saw every sensor message up
// to its step.
#include <gtest/gtest.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <unistd.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "report.h"
#include "specht/io/ros_messages.h"
#include "specht/io/trajectory_io.h"
#include "specht/net/dds.h"
#include "specht/pipeline/nodes.h"
#include "test_support.h"

namespace specht::pipeline {
namespace {

using std::chrono::milliseconds;

constexpr double kMaxSteerRate = 60 * M_PI / 180;  // car.max_steer_rate_deg_s

// The command for the step at `t`, from the latest odometry reading before it: weave
// along, pulled back towards y = odometry's start.
io::ros::AckermannDrive Command(Stamp t, double odom_y) {
  const double s = 1e-9 * static_cast<double>(t.ns % 1000000000000LL);
  io::ros::AckermannDrive m;
  m.header.stamp = t;
  m.speed = static_cast<float>(2.0 + std::sin(0.5 * s));
  m.steering_angle = static_cast<float>(0.25 * std::sin(s) - 0.05 * odom_y);
  return m;
}

TEST(SimNodeTest, LockstepDriveOverDdsEqualsTheInProcessDrive) {
  const std::string scenario = testing::SourceDir() + "/datasets/scenarios/parking-lot.yaml";
  const std::string dir = testing::TempDir("sim_node");
  const int domain = 1 + getpid() % 200;
  constexpr double kDuration = 8.0;

  // In process: the same commander, fed by the simulator's odometry directly.
  const sim::Scenario s = sim::LoadScenario(scenario);
  sim::Simulator sim(s, s.seed);
  double odom_y = 0;
  const Trajectory expected = DriveSimulatedCar(
      sim, kDuration, 20.0,
      [&](Stamp t, const sim::Simulator&) {
        const auto m = Command(t, odom_y);
        return std::optional(EgoCommandOf(m.speed, m.steering_angle, m.steering_angle_velocity, kMaxSteerRate));
      },
      [&](Stamp, const mrpt::obs::CObservation::Ptr& o) {
        if (const auto odom = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o))
          odom_y = odom->odometry.y();
      });
  io::WriteTum(expected, dir + "/expected.tum");

  // Over DDS: the node in its own process, this test its commander.
  testing::BackgroundSpecht node("node sim '" + scenario + "' --duration " + std::to_string(kDuration) +
                                 " -q --domain " + std::to_string(domain) + " -o '" + dir + "/node'");
  net::Options options;
  options.domain = domain;
  net::Participant participant(options);
  net::Reader clock(participant, "/clock", "rosgraph_msgs/msg/Clock", net::Qos::kClock);
  net::Reader odometry(participant, "/odom", "nav_msgs/msg/Odometry", net::Qos::kKeepAll);
  net::Writer drive(participant, "/drive", "ackermann_msgs/msg/AckermannDriveStamped", net::Qos::kKeepAll);
  net::WaitSet wait(participant);
  wait.Attach(clock);
  odom_y = 0;
  Stamp answered{-1};
  int commands = 0;
  const Stamp end{sim::Simulator::kEpochNs + static_cast<int64_t>(kDuration * 1e9) - 50'000'000};  // the last step
  while (answered < end) {
    ASSERT_TRUE(wait.Wait(milliseconds(20000))) << "no /clock from the node";
    for (const auto& c : clock.Take()) {
      const Stamp t = io::ros::DecodeClock(c.cdr);
      if (t <= answered) continue;  // a repeat while the node waits
      for (const auto& o : odometry.Take()) {
        const auto odom = io::ros::DecodeOdometry(o.cdr);
        EXPECT_LE(odom.header.stamp, t);
        odom_y = odom.pose.y;
      }
      drive.Write(io::ros::Encode(Command(t, odom_y)), t);
      answered = t;
      ++commands;
    }
  }
  const auto r = node.Wait();
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(commands, static_cast<int>(expected.size()) - 1);
  EXPECT_TRUE(testing::ReadFile(dir + "/node/ground_truth.tum") == testing::ReadFile(dir + "/expected.tum"));
  const auto report = Report(dir + "/node");
  EXPECT_EQ(report["counts"]["commands"], commands);
  EXPECT_GT(report["counts"]["published"]["/scan"].get<int>(), 50);
  // It drove somewhere: 8 s at 1–3 m/s.
  EXPECT_GT(PathLength(expected), 10.0);
}

// Without a commander the lockstep node does not hang: it ends after
// node.command_timeout_s with what it simulated, status incomplete.
TEST(SimNodeTest, LockstepWithoutCommandsEndsAfterTheTimeout) {
  const std::string dir = testing::TempDir("sim_node_timeout");
  const auto r = testing::RunSpecht("node sim '" + testing::SourceDir() +
                                    "/datasets/scenarios/parking-lot.yaml' -q --set node.command_timeout_s=0.5 "
                                    "--domain " +
                                    std::to_string(1 + getpid() % 200) + " -o '" + dir + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const auto report = Report(dir);
  EXPECT_EQ(report["status"], "incomplete");
  EXPECT_NE(report["error"].get<std::string>().find("no command on /drive"), std::string::npos);
}

}  // namespace
}  // namespace specht::pipeline
