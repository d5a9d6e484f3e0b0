// The video of a closed-loop drive: the truth beside what the car believes, the
// whole site from above, kVideoHz frames a simulated second, played at kPlaySpeed×.
//   left   the truth: the scenario's true grid, the simulator's agents, the car
//          where it is
//   right  the world model the car drives on: its static and cost layers, the
//          tracks with their predictions, perception's obstacles, the car where it
//          believes it is and the path it follows
// Both are internal::BirdsEye pictures; only the snapshot and the pose differ.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <string>
#include <vector>

#include "internal/perception_video.h"
#include "specht/io/video.h"
#include "specht/plan/car.h"
#include "specht/sim/simulator.h"
#include "specht/world/world_model.h"

namespace specht::pipeline::internal {

class LoopVideo {
 public:
  static constexpr double kVideoHz = 5, kPlaySpeed = 2;
  static constexpr int kSidePx = 540;

  LoopVideo(const std::string& path, const mrpt::maps::COccupancyGridMap2D& true_grid,
            const world::WorldModelOptions& options, Stamp start);
  // Once per control step; draws a frame when one is due. `believed`: the car's box
  // centre as it believes it; `path`: what it follows (map frame).
  void Step(const sim::Simulator& sim, const world::Snapshot& seen, const sim::Pose2& believed,
            const std::vector<plan::Pose>& path);
  // Finishes the file; returns what was written (io::VideoSink::Close).
  std::string Close() { return sink_.Close(); }

 private:
  io::VideoSink sink_;
  world::WorldModel truth_;
  BirdsEyeView view_;
  double next_s_ = 0;
};

}  // namespace specht::pipeline::internal
