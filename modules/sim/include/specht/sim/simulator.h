// specht/sim/simulator.h: steps a scenario in time and produces sensor observations
// (MRPT types, as a real car's drivers would) with their ground truth.
//
// Time advances in fixed steps of 10 ms from t = 0 (stamped from 2026-01-01T00:00Z).
// Every mover integrates its motion model (motion.h). Sensors fire at their rates:
//   LiDAR     ray cast from the mount against the world and the movers' boxes;
//             Gaussian range noise, dropouts (invalid), no return beyond max range.
//   odometry  the true body-frame increment with multiplicative noise and a
//             systematic yaw drift per metre, chained into an odometry pose:
//               Δx' = Δx (1 + σ_t n₁),  Δθ' = Δθ (1 + σ_r n₂) + k_θ |Δx|
//   IMU       gyro z = true yaw rate + bias + noise; accelerometer x = true
//             longitudinal acceleration, y = v·ω (centripetal), each + noise.
// Random streams are separate for motion and for each sensor and all derive from the
// seed, so the same scenario and seed give identical outputs, and a different seed
// changes both noise and agent behaviour.
#pragma once

#include <mrpt/obs/CObservation.h>

#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "specht/core/time.h"
#include "specht/sim/camera.h"
#include "specht/sim/motion.h"
#include "specht/sim/scenario.h"
#include "specht/sim/world.h"

namespace specht::sim {

struct AgentTruth {
  int id = 0;
  AgentClass cls = AgentClass::kPedestrian;
  Pose2 pose;
  double speed_mps = 0, yaw_rate = 0;
  double length_m = 0, width_m = 0;
};

class Simulator {
 public:
  static constexpr double kStepS = 0.01;
  static constexpr int64_t kEpochNs = 1767225600LL * 1000000000LL;  // 2026-01-01T00:00:00Z

  // With `sprites` the camera shows agents as photographs (sprites.h), else as boxes.
  Simulator(const Scenario& scenario, uint64_t seed, const SpriteLibrary* sprites = nullptr);

  using Sink = std::function<void(Stamp, const mrpt::obs::CObservation::Ptr&)>;
  using StereoSink = std::function<void(Stamp, const StereoFrame&)>;
  // One 10 ms step; observations due in it go to `sink` in time order, rendered
  // stereo frames (when the scenario has a camera) to `stereo`.
  void Step(const Sink& sink, const StereoSink& stereo = nullptr);
  // Closed loop: from the next step on, the ego drives by these commands (see
  // RouteFollower::StepCommanded) instead of following its route.
  struct EgoCommand {
    double speed_mps = 0, steer_rad = 0, steer_rate_rad_s = 1.0;
  };
  void CommandEgo(const EgoCommand& command) { ego_command_ = command; }
  // The agents as the camera sees them (boxes with class heights and KITTI names).
  std::vector<Box3> AgentBoxes() const;

  double time_s() const { return SecondsAt(stamp()); }
  Stamp stamp() const { return Stamp{kEpochNs + step_ * 10'000'000LL}; }
  // The drive's time of a stamp the simulator gave (its step × kStepS).
  static double SecondsAt(Stamp t) { return static_cast<double>((t.ns - kEpochNs) / 10'000'000LL) * kStepS; }
  const MoverState& ego() const { return ego_.state(); }
  std::vector<AgentTruth> agents() const;  // the agents that have started
  const World& world() const { return world_; }
  const Scenario& scenario() const { return scenario_; }
  // True when the step that just ran produced a LiDAR scan.
  bool scanned() const { return scanned_; }
  // Wall time spent rendering stereo frames so far.
  double render_seconds() const { return render_s_; }

 private:
  mrpt::obs::CObservation::Ptr Scan();
  mrpt::obs::CObservation::Ptr Odometry();
  mrpt::obs::CObservation::Ptr Imu();

  const Scenario& scenario_;
  World world_;
  RouteFollower ego_;
  std::optional<EgoCommand> ego_command_;
  std::vector<RouteFollower> agents_;
  std::mt19937_64 motion_rng_, lidar_rng_, odometry_rng_, imu_rng_;
  int64_t step_ = 0;
  bool scanned_ = false;
  double render_s_ = 0;
  std::optional<StereoRenderer> stereo_;
  Pose2 ego_at_last_odometry_;
  Pose2 odometry_;  // chained noisy odometry
};

}  // namespace specht::sim
