#include "internal/loop_video.h"

#include <algorithm>
#include <opencv2/core.hpp>

#include "internal/loop_geometry.h"
#include "internal/loop_perception.h"
#include "internal/perception_video.h"

namespace specht::pipeline::internal {

LoopVideo::LoopVideo(const std::string& path, const mrpt::maps::COccupancyGridMap2D& true_grid,
                     const world::WorldModelOptions& options, Stamp start)
    : sink_(path, kPlaySpeed * kVideoHz), truth_(options) {
  // The whole site, fixed: only the road users and the car move between frames, which
  // keeps the MP4 small (a view that follows the car redraws every pixel).
  const double w = true_grid.getXMax() - true_grid.getXMin(), h = true_grid.getYMax() - true_grid.getYMin();
  view_ = {(true_grid.getXMin() + true_grid.getXMax()) / 2, (true_grid.getYMin() + true_grid.getYMax()) / 2,
           std::max(w, h), kSidePx};
  truth_.SetStaticMap(true_grid, start);
}

void LoopVideo::Step(const sim::Simulator& sim, const world::Snapshot& seen, const sim::Pose2& believed,
                     const std::vector<plan::Pose>& path) {
  const double t = sim.time_s();
  if (t + 1e-9 < next_s_) return;
  next_s_ = t + 1 / kVideoHz;
  world::WorldUpdate u;
  u.stamp = sim.stamp();
  u.tracks.emplace();
  std::vector<types::Obstacle> boxes;  // the tracks say it all; obstacles would linger as a trail
  AgentsAsPerceived(sim.agents(), sim.stamp(), *u.tracks, boxes);
  truth_.Apply(u);
  cv::Mat left = BirdsEye(*truth_.snapshot(), Pose3(sim.ego().pose), t, view_);
  std::vector<cv::Point2d> line;
  for (const auto& p : path) line.emplace_back(p.x, p.y);
  cv::Mat right = BirdsEye(seen, Pose3(believed), t, view_, line);
  Label(left, "truth", {4, kSidePx - 8}, cv::Scalar(255, 255, 255));
  Label(right, "world model: what the car drives on", {4, kSidePx - 8}, cv::Scalar(255, 255, 255));
  cv::Mat frame;
  cv::hconcat(left, right, frame);
  sink_.Write(frame);
}

}  // namespace specht::pipeline::internal
