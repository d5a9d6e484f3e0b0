#include "specht/sim/simulator.h"

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <chrono>
#include <cmath>

#include "internal/geometry.h"

namespace specht::sim {
namespace {

std::mt19937_64 Stream(uint64_t seed, uint64_t salt) {
  std::seed_seq seq{static_cast<uint32_t>(seed), static_cast<uint32_t>(seed >> 32), static_cast<uint32_t>(salt)};
  return std::mt19937_64(seq);
}

// Whether a sensor at `rate_hz` samples at step `step`: when the count of its periods
// since the start, floor(step · rate · Δt), goes up. A rate that divides the step rate
// samples every 1/(rate · Δt) steps exactly; another keeps its average rate on the
// nearest later steps (40 Hz: every 3, 2, 3, 2 … steps of 10 ms).
bool Due(int64_t step, double rate_hz) {
  const auto periods = [rate_hz](int64_t k) {
    return std::floor(static_cast<double>(k) * rate_hz * Simulator::kStepS + 1e-9);
  };
  return periods(step) > periods(step - 1);
}

// Pose b seen from pose a.
Pose2 Relative(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.yaw_rad), s = std::sin(a.yaw_rad), dx = b.x - a.x, dy = b.y - a.y;
  return {c * dx + s * dy, -s * dx + c * dy, internal::WrapAngle(b.yaw_rad - a.yaw_rad)};
}

Pose2 Compose(const Pose2& a, const Pose2& d) {
  const double c = std::cos(a.yaw_rad), s = std::sin(a.yaw_rad);
  return {a.x + c * d.x - s * d.y, a.y + s * d.x + c * d.y, internal::WrapAngle(a.yaw_rad + d.yaw_rad)};
}

}  // namespace

Simulator::Simulator(const Scenario& scenario, uint64_t seed, const SpriteLibrary* sprites)
    : scenario_(scenario),
      world_(scenario),
      ego_(scenario.ego.route, scenario.ego.loop, EgoMotion(scenario.ego), scenario.ego.start),
      motion_rng_(Stream(seed, 1)),
      lidar_rng_(Stream(seed, 2)),
      odometry_rng_(Stream(seed, 3)),
      imu_rng_(Stream(seed, 4)),
      ego_at_last_odometry_(scenario.ego.start) {
  if (scenario.stereo) stereo_.emplace(scenario, world_, *scenario.stereo, sprites);
  for (const auto& a : scenario.agents) {
    const Waypoint& first = a.route.front();
    const Waypoint& second = a.route[1];
    const Pose2 start{first.p.x, first.p.y, std::atan2(second.p.y - first.p.y, second.p.x - first.p.x)};
    MotionParams motion = SampleMotion(a.cls, motion_rng_);
    if (a.max_speed_mps > 0) motion.cruise_mps = std::min(motion.cruise_mps, a.max_speed_mps);
    agents_.emplace_back(a.route, a.loop, motion, start, /*back_and_forth=*/true);
  }
}

std::vector<AgentTruth> Simulator::agents() const {
  std::vector<AgentTruth> out;
  for (size_t i = 0; i < agents_.size(); ++i) {
    if (time_s() < scenario_.agents[i].start_s) continue;
    const auto& s = agents_[i].state();
    const auto& p = agents_[i].params();
    out.push_back(
        {scenario_.agents[i].id, scenario_.agents[i].cls, s.pose, s.speed_mps, s.yaw_rate, p.length_m, p.width_m});
  }
  return out;
}

std::vector<Box3> Simulator::AgentBoxes() const {
  std::vector<Box3> boxes;
  for (const auto& a : agents()) {
    const double height = a.cls == AgentClass::kCar ? 1.5 : a.cls == AgentClass::kCyclist ? 1.7 : 1.75;
    const char* name = a.cls == AgentClass::kCar ? "Car" : a.cls == AgentClass::kCyclist ? "Cyclist" : "Pedestrian";
    std::string sprite;
    for (const auto& spec : scenario_.agents)
      if (spec.id == a.id) sprite = spec.sprite;
    boxes.push_back({a.pose, a.length_m, a.width_m, height, a.id, name, sprite});
  }
  return boxes;
}

void Simulator::Step(const Sink& sink, const StereoSink& stereo) {
  ++step_;
  if (ego_command_)
    ego_.StepCommanded(kStepS, ego_command_->speed_mps, ego_command_->steer_rad, ego_command_->steer_rate_rad_s);
  else
    ego_.Step(kStepS, motion_rng_);
  for (size_t i = 0; i < agents_.size(); ++i) {
    if (time_s() >= scenario_.agents[i].start_s) agents_[i].Step(kStepS, motion_rng_);
  }
  const Stamp now = stamp();
  scanned_ = false;
  if (Due(step_, scenario_.imu.rate_hz)) sink(now, Imu());
  if (Due(step_, scenario_.odometry.rate_hz)) sink(now, Odometry());
  if (Due(step_, scenario_.lidar.rate_hz)) {
    sink(now, Scan());
    scanned_ = true;
  }
  if (stereo_ && stereo && Due(step_, scenario_.stereo->rate_hz)) {
    const auto t0 = std::chrono::steady_clock::now();
    const StereoFrame frame = stereo_->Render(ego_.state().pose, AgentBoxes());
    render_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    stereo(now, frame);
  }
}

mrpt::obs::CObservation::Ptr Simulator::Scan() {
  const LidarSpec& l = scenario_.lidar;
  const Pose2 sensor = Compose(ego_.state().pose, l.mount);
  std::vector<Segment> moving;
  for (const auto& a : agents()) {
    const auto box = BoxOutline(a.pose, a.length_m, a.width_m);
    moving.insert(moving.end(), box.begin(), box.end());
  }
  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  scan->aperture = static_cast<float>(l.fov_rad);
  scan->rightToLeft = true;
  scan->maxRange = static_cast<float>(l.max_range_m);
  scan->resizeScan(l.beams);
  std::normal_distribution<double> noise(0.0, l.range_noise_m);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int i = 0; i < l.beams; ++i) {
    const double angle = sensor.yaw_rad - l.fov_rad / 2 + l.fov_rad * i / (l.beams - 1);
    const double r = world_.RayCast({sensor.x, sensor.y}, angle, l.max_range_m, moving);
    const double noisy = r + (l.range_noise_m > 0 ? noise(lidar_rng_) : 0.0);
    const bool dropped = u01(lidar_rng_) < l.dropout;
    const bool valid = std::isfinite(r) && !dropped && noisy > 0 && noisy < l.max_range_m;
    scan->setScanRange(i, valid ? static_cast<float>(noisy) : static_cast<float>(l.max_range_m));
    scan->setScanRangeValidity(i, valid);
  }
  scan->sensorPose = mrpt::poses::CPose3D(l.mount.x, l.mount.y, 0.3, l.mount.yaw_rad, 0, 0);
  scan->sensorLabel = "LASER";
  scan->timestamp = ToMrpt(stamp());
  return scan;
}

mrpt::obs::CObservation::Ptr Simulator::Odometry() {
  const OdometrySpec& o = scenario_.odometry;
  const Pose2 truth = ego_.state().pose;
  const Pose2 d = Relative(ego_at_last_odometry_, truth);
  ego_at_last_odometry_ = truth;
  std::normal_distribution<double> n01(0.0, 1.0);
  const double dist = std::hypot(d.x, d.y);
  const Pose2 noisy{d.x * (1 + o.translation_noise * n01(odometry_rng_)), d.y,
                    d.yaw_rad * (1 + o.rotation_noise * n01(odometry_rng_)) + o.rotation_per_metre * dist};
  odometry_ = Compose(odometry_, noisy);
  auto obs = mrpt::obs::CObservationOdometry::Create();
  obs->odometry = mrpt::poses::CPose2D(odometry_.x, odometry_.y, odometry_.yaw_rad);
  obs->hasVelocities = true;
  obs->velocityLocal = mrpt::math::TTwist2D(ego_.state().speed_mps, 0, ego_.state().yaw_rate);
  obs->sensorLabel = "ODOMETRY";
  obs->timestamp = ToMrpt(stamp());
  return obs;
}

mrpt::obs::CObservation::Ptr Simulator::Imu() {
  const ImuSpec& m = scenario_.imu;
  std::normal_distribution<double> gyro(0.0, m.gyro_noise_rad_s), accel(0.0, m.accel_noise_mps2);
  const MoverState& s = ego_.state();
  auto obs = mrpt::obs::CObservationIMU::Create();
  obs->set(mrpt::obs::IMU_WZ, s.yaw_rate + m.gyro_bias_rad_s + gyro(imu_rng_));
  obs->set(mrpt::obs::IMU_X_ACC, s.accel_mps2 + accel(imu_rng_));
  obs->set(mrpt::obs::IMU_Y_ACC, s.speed_mps * s.yaw_rate + accel(imu_rng_));
  obs->sensorLabel = "IMU";
  obs->timestamp = ToMrpt(stamp());
  return obs;
}

}  // namespace specht::sim
