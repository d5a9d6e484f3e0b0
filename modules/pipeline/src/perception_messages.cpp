#include "internal/perception_messages.h"

#include <cmath>

namespace specht::pipeline::internal {

namespace ros = io::ros;

ros::Obstacles ObstaclesToRos(const std::vector<types::Obstacle>& obstacles, Stamp stamp, const char* frame) {
  ros::Obstacles m{{stamp, frame}, {}};
  for (const auto& o : obstacles) {
    const auto& c = o.covariance_xy;
    m.obstacles.push_back({o.id,
                           o.cls,
                           o.x_m,
                           o.y_m,
                           o.z_m,
                           o.radius_m,
                           o.length_m,
                           o.width_m,
                           o.yaw_rad,
                           {c(0, 0), c(0, 1), c(1, 0), c(1, 1)},
                           o.score,
                           o.range_m});
  }
  return m;
}

std::vector<types::Obstacle> ObstaclesFromRos(const ros::Obstacles& m) {
  std::vector<types::Obstacle> obstacles;
  for (const auto& r : m.obstacles) {
    types::Obstacle o;
    o.id = r.id, o.cls = r.cls, o.stamp = m.header.stamp;
    o.x_m = r.x, o.y_m = r.y, o.z_m = r.z, o.radius_m = r.radius, o.length_m = r.length, o.width_m = r.width;
    o.yaw_rad = r.yaw;
    o.covariance_xy = {r.covariance_xy[0], r.covariance_xy[1], r.covariance_xy[2], r.covariance_xy[3]};
    o.score = r.score, o.range_m = r.range;
    obstacles.push_back(o);
  }
  return obstacles;
}

ros::Tracks TracksToRos(const std::vector<types::Track>& tracks, Stamp stamp) {
  ros::Tracks m{{stamp, "map"}, {}};
  for (const auto& t : tracks) {
    ros::Track r;
    r.id = t.id, r.cls = t.cls, r.x = t.x_m, r.y = t.y_m, r.vx = t.vx_mps, r.vy = t.vy_mps;
    std::copy(t.covariance.val, t.covariance.val + 16, r.covariance.begin());
    r.length = t.length_m, r.width = t.width_m, r.yaw = t.yaw_rad, r.state = t.state, r.motion_model = t.motion_model;
    for (const auto& p : t.history) r.history.push_back({p.stamp, p.x_m, p.y_m});
    for (const auto& p : t.prediction)
      r.prediction.push_back(
          {p.dt_s, p.x_m, p.y_m, {p.covariance(0, 0), p.covariance(0, 1), p.covariance(1, 0), p.covariance(1, 1)}});
    for (const auto& [cls, p] : t.class_probabilities) r.classes.push_back(cls), r.probabilities.push_back(p);
    m.tracks.push_back(std::move(r));
  }
  return m;
}

std::vector<types::Track> TracksFromRos(const ros::Tracks& m) {
  std::vector<types::Track> tracks;
  for (const auto& r : m.tracks) {
    types::Track t;
    t.id = r.id, t.cls = r.cls, t.stamp = m.header.stamp, t.x_m = r.x, t.y_m = r.y, t.vx_mps = r.vx, t.vy_mps = r.vy;
    std::copy(r.covariance.begin(), r.covariance.end(), t.covariance.val);
    t.length_m = r.length, t.width_m = r.width, t.yaw_rad = r.yaw, t.state = r.state, t.motion_model = r.motion_model;
    for (const auto& p : r.history) t.history.push_back({p.stamp, p.x, p.y});
    for (const auto& p : r.prediction) {
      const auto& c = p.covariance_xy;
      t.prediction.push_back({p.dt, p.x, p.y, cv::Matx22d(c[0], c[1], c[2], c[3])});
    }
    for (size_t i = 0; i < r.classes.size() && i < r.probabilities.size(); ++i)
      t.class_probabilities[r.classes[i]] = r.probabilities[i];
    tracks.push_back(std::move(t));
  }
  return tracks;
}

ros::Odometry PoseToRos(const sim::Pose2& p, Stamp stamp) {
  ros::Odometry m;
  m.header = {stamp, "map"};
  m.child_frame_id = "base_link";
  m.pose.x = p.x, m.pose.y = p.y, m.pose.qz = std::sin(p.yaw_rad / 2), m.pose.qw = std::cos(p.yaw_rad / 2);
  return m;
}

sim::Pose2 PoseFromRos(const ros::Odometry& m) { return {m.pose.x, m.pose.y, m.pose.Yaw()}; }

}  // namespace specht::pipeline::internal
