#include "internal/loop_perception.h"

#include <algorithm>
#include <cmath>

#include "internal/sim_stereo.h"
#include "specht/core/error.h"
#include "specht/pipeline/perception_eval.h"

namespace specht::pipeline::internal {
namespace {

Box BoxOf(double x, double y, double yaw, double length, double width, double radius) {
  if (length <= 0 || width <= 0) length = width = 2 * std::max(radius, 0.5);
  return {x, y, yaw, length / 2, width / 2};
}

}  // namespace

types::Obstacle InCarFrame(types::Obstacle o, const sim::Pose2& truth) {
  const double dx = o.x_m - truth.x, dy = o.y_m - truth.y, c = std::cos(truth.yaw_rad), s = std::sin(truth.yaw_rad);
  o.x_m = c * dx + s * dy, o.y_m = -s * dx + c * dy, o.yaw_rad -= truth.yaw_rad;
  return o;
}

Perceived PerceivedFrom(const world::Snapshot& s, double age_s) {
  Perceived p;
  for (const auto& t : s.tracks)
    p.tracks.push_back(
        {t.id, t.cls, BoxOf(t.x_m + t.vx_mps * age_s, t.y_m + t.vy_mps * age_s, t.yaw_rad, t.length_m, t.width_m, 0.5),
         t.vx_mps, t.vy_mps});
  // The latest frame only: the layer keeps obstacles for their lifetime, and a moving
  // agent's older positions are places it has left.
  for (const auto& o : s.obstacles)
    if (o.stamp == s.obstacles_stamp)
      p.obstacles.push_back({o.id, o.cls, BoxOf(o.x_m, o.y_m, o.yaw_rad, o.length_m, o.width_m, o.radius_m), 0, 0});
  return p;
}

void ForEachReturn(const mrpt::obs::CObservation2DRangeScan& scan, const sim::Pose2& at,
                   const std::function<void(size_t, const cv::Point2d&)>& visit) {
  const double c = std::cos(at.yaw_rad), s = std::sin(at.yaw_rad);
  const double sx = at.x + c * scan.sensorPose.x() - s * scan.sensorPose.y();
  const double sy = at.y + s * scan.sensorPose.x() + c * scan.sensorPose.y();
  const double yaw = at.yaw_rad + scan.sensorPose.yaw();
  const size_t n = scan.getScanSize();
  for (size_t i = 0; i < n; ++i) {
    if (!scan.getScanRangeValidity(i)) continue;
    const double a = yaw - scan.aperture / 2 + scan.aperture * static_cast<double>(i) / (n - 1);
    const double r = scan.getScanRange(i);
    visit(i, {sx + r * std::cos(a), sy + r * std::sin(a)});
  }
}

mrpt::obs::CObservation2DRangeScan::Ptr WithoutReturnsOn(const mrpt::obs::CObservation2DRangeScan& in,
                                                         const sim::Pose2& at, const std::vector<SeenObject>& tracks) {
  auto scan = mrpt::obs::CObservation2DRangeScan::Create(in);
  if (tracks.empty()) return scan;
  ForEachReturn(in, at, [&](size_t i, const cv::Point2d& hit) {
    for (const auto& t : tracks)
      if (PointToBox(hit, t.box) < 0.3) {
        scan->setScanRangeValidity(i, false);
        break;
      }
  });
  return scan;
}

void AgentsAsPerceived(const std::vector<sim::AgentTruth>& agents, Stamp stamp, std::vector<types::Track>& tracks,
                       std::vector<types::Obstacle>& obstacles) {
  for (const auto& a : agents) {
    types::Track t;
    t.id = a.id, t.cls = sim::Name(a.cls), t.stamp = stamp, t.state = "confirmed";
    t.x_m = a.pose.x, t.y_m = a.pose.y, t.yaw_rad = a.pose.yaw_rad;
    t.vx_mps = a.speed_mps * std::cos(a.pose.yaw_rad), t.vy_mps = a.speed_mps * std::sin(a.pose.yaw_rad);
    t.length_m = a.length_m, t.width_m = a.width_m;
    tracks.push_back(t);
    types::Obstacle o;
    o.id = a.id, o.cls = t.cls, o.stamp = t.stamp, o.x_m = t.x_m, o.y_m = t.y_m;
    o.length_m = a.length_m, o.width_m = a.width_m, o.yaw_rad = a.pose.yaw_rad;
    o.radius_m = std::max(a.length_m, a.width_m) / 2, o.score = 1;
    obstacles.push_back(o);
  }
}

LoopPerception::LoopPerception(const std::string& mode, const track::TrackerOptions& tracking, world::WorldModel& world,
                               const LoopCameraConfig& camera)
    : mode_(mode), world_(world) {
  if (mode == "detections") {
    tracker_.emplace(tracking);
  } else if (mode == "camera") {  // loads the detector: a missing model fails here, before the car moves
    camera_ = std::make_unique<StereoPerception>(camera.sgm, camera.detector, camera.fusion, camera.data_dir,
                                                 camera.downsample);
    tracker_.emplace(tracking);
  } else if (mode != "truth") {
    throw InputError("closed_loop.perception: unknown mode '" + mode + "'");
  }
}

LoopPerception::~LoopPerception() = default;

std::vector<types::Track> LoopPerception::Oracle(const std::vector<sim::AgentTruth>& agents, Stamp stamp) {
  std::vector<types::Track> tracks;
  std::vector<types::Obstacle> obstacles;
  AgentsAsPerceived(agents, stamp, tracks, obstacles);
  Write(tracks, std::move(obstacles), stamp);
  return tracks;
}

std::vector<types::Obstacle> PlacedAt(std::vector<types::Obstacle> in_car, const sim::Pose2& believed) {
  const double c = std::cos(believed.yaw_rad), s = std::sin(believed.yaw_rad);
  for (auto& o : in_car) {
    const double x = o.x_m, y = o.y_m;
    o.x_m = believed.x + c * x - s * y, o.y_m = believed.y + s * x + c * y, o.yaw_rad += believed.yaw_rad;
  }
  return in_car;
}

std::vector<types::Track> LoopPerception::Detections(std::vector<types::Obstacle> in_car, Stamp stamp,
                                                     const sim::Pose2& believed) {
  return Publish(PlacedAt(std::move(in_car), believed), stamp);
}

void LoopPerception::Tracked(std::vector<types::Track> tracks, std::vector<types::Obstacle> obstacles, Stamp stamp) {
  detections_ += static_cast<long>(obstacles.size());
  ++tracked_elsewhere_;
  Write(std::move(tracks), std::move(obstacles), stamp);
}

std::vector<types::Track> LoopPerception::Camera(const mrpt::obs::CObservationStereoImages& frame, Stamp stamp,
                                                 const sim::Pose2& believed) {
  PerceivedFrame seen = camera_->Process(frame, Pose3(believed), stamp);
  return Publish(std::move(seen.obstacles), stamp);
}

std::vector<types::Track> LoopPerception::Publish(std::vector<types::Obstacle> obstacles, Stamp stamp) {
  tracker_->Update(obstacles, stamp);
  std::vector<types::Track> tracks = tracker_->Tracks();
  detections_ += static_cast<long>(obstacles.size());
  Write(tracks, std::move(obstacles), stamp);
  return tracks;
}

void LoopPerception::Write(std::vector<types::Track> tracks, std::vector<types::Obstacle> obstacles, Stamp stamp) {
  world::WorldUpdate u;
  u.stamp = stamp;
  u.tracks = std::move(tracks);
  u.obstacles = std::move(obstacles);
  world_.Apply(u);
  ++frames_;
}

void PerceptionScore::Frame(const std::vector<sim::AgentTruth>& in_view, const std::vector<sim::AgentTruth>& all,
                            const std::vector<types::Track>& tracks) {
  const auto near = [&](double x, double y, double ax, double ay) { return std::hypot(x - ax, y - ay) <= match_m_; };
  for (const auto& a : in_view) {
    auto& c = by_class_[sim::Name(a.cls)];
    ++c.in_view;
    c.found += std::any_of(tracks.begin(), tracks.end(),
                           [&](const types::Track& t) { return near(t.x_m, t.y_m, a.pose.x, a.pose.y); });
  }
  for (const auto& t : tracks) {
    auto& c = by_class_[t.cls];
    ++c.reported;
    c.right += std::any_of(all.begin(), all.end(),
                           [&](const sim::AgentTruth& a) { return near(t.x_m, t.y_m, a.pose.x, a.pose.y); });
  }
}

nlohmann::json LoopPerception::ToJson() const {
  nlohmann::json j = {{"mode", mode_}, {"frames", frames_}, {"detections", detections_}};
  if (tracked_elsewhere_ > 0) j["tracked_by_perception_node"] = tracked_elsewhere_;
  return j;
}

nlohmann::json PerceptionScore::ToJson() const {
  nlohmann::json classes = nlohmann::json::object();
  for (const auto& [cls, c] : by_class_)
    classes[cls] = {
        {"recall", c.in_view ? nlohmann::json(static_cast<double>(c.found) / c.in_view) : nlohmann::json()},
        {"precision", c.reported ? nlohmann::json(static_cast<double>(c.right) / c.reported) : nlohmann::json()},
        {"in_view", c.in_view},
        {"found", c.found},
        {"reported", c.reported},
        {"right", c.right}};
  return {{"match_m", match_m_}, {"by_class", classes}};
}

}  // namespace specht::pipeline::internal
