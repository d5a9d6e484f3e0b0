// What the car perceives in the closed loop, written into the world model — the only
// thing the mission state machine reads about other road users.
//   truth       the oracle, for side-by-side runs: at every control step each agent
//               the simulator has started becomes a confirmed track and an obstacle
//               with its true box and its velocity along its heading
//   detections  the simulator's noisy detections (sim/detections.h: range, line of
//               sight, misses, false alarms, class errors) at their rate, taken
//               from the true car and placed in the map frame at the car's *believed*
//               pose (a localisation error moves what it sees with it) → the
//               multi-object tracker (track/tracker.h) → the track layer, and the
//               frame's detections → the obstacle layer
//   camera      each stereo frame the simulator renders (Camera): our SGM and the
//               CNN detector (stereo_perception.h), box fusion placed at the
//               believed pose → the tracker → the track and obstacle layers
// In-loop scoring against the simulator's truth (never fed back): at each perception
// frame, an agent in view (camera: as `specht eval perception` counts one at its
// defaults, perception_eval.h) counts as found when a reported track lies within
// match_m of it (recall, by the agent's class), and a track is right when an agent
// lies within match_m of it (precision, by the track's class).
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "internal/loop_geometry.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/pipeline/stereo_perception.h"
#include "specht/sim/detections.h"
#include "specht/sim/simulator.h"
#include "specht/track/tracker.h"
#include "specht/world/world_model.h"

namespace specht::pipeline::internal {

// A perceived road user as the closed loop's checks see it.
struct SeenObject {
  long id = 0;
  std::string cls;
  Box box{};
  double vx_mps = 0, vy_mps = 0;
  std::string Name() const { return cls + " " + std::to_string(id); }
};

// The tracks and the latest frame's obstacles of a world-model snapshot.
struct Perceived {
  std::vector<SeenObject> tracks, obstacles;
};
Perceived PerceivedFrom(const world::Snapshot& snapshot, double age_s = 0);

// Each valid return of `scan` as a point, the scan taken with the car's box centre at
// `at`: visit(beam index, point in `at`'s frame).
void ForEachReturn(const mrpt::obs::CObservation2DRangeScan& scan, const sim::Pose2& at,
                   const std::function<void(size_t, const cv::Point2d&)>& visit);

// A copy of `scan`, taken at the believed box-centre pose `at`, with every return
// within 0.3 m of a track's box marked invalid: what tells road users from the
// static world before scans reach SLAM and the map.
mrpt::obs::CObservation2DRangeScan::Ptr WithoutReturnsOn(const mrpt::obs::CObservation2DRangeScan& scan,
                                                         const sim::Pose2& at, const std::vector<SeenObject>& tracks);

struct PerceptionCounts {
  long found = 0, in_view = 0;   // recall
  long right = 0, reported = 0;  // precision
};

// A fault: from at_s (≥ 0) for for_s, perception delivers no frame (a blind camera).
// The simulator's agents as perception would report them, exactly (perception
// truth, and the truth side of the run video): confirmed tracks and obstacles.
void AgentsAsPerceived(const std::vector<sim::AgentTruth>& agents, Stamp stamp, std::vector<types::Track>& tracks,
                       std::vector<types::Obstacle>& obstacles);

struct Blindness {
  double at_s = -1, for_s = 0;
  bool Covers(double t_s) const { return at_s >= 0 && t_s >= at_s && t_s < at_s + for_s; }
};

class LoopPerception {
 public:
  LoopPerception(const std::string& mode, double control_hz, const sim::SyntheticDetectionOptions& detection,
                 const track::TrackerOptions& tracking, double match_m, uint64_t seed, world::WorldModel& world,
                 Blindness blind = {}, const LoopCameraConfig& camera = {});
  ~LoopPerception();
  // After every simulator step (and once before the first): writes the world model
  // when a frame is due. `believed` is where the car thinks its box centre is.
  void Step(const sim::Simulator& sim, const sim::Pose2& believed);
  // Mode camera: one rendered stereo frame, as the simulator delivers it.
  void Camera(const sim::Simulator& sim, const sim::StereoFrame& frame, const sim::Pose2& believed);
  nlohmann::json ToJson() const;  // recall and precision per class, frames, detections

 private:
  void Score(const std::vector<sim::AgentTruth>& in_view, const std::vector<sim::AgentTruth>& all,
             const std::vector<types::Track>& tracks);
  // Tracks the frame's obstacles (map frame) and writes both layers.
  void Publish(std::vector<types::Obstacle> obstacles, const sim::Simulator& sim,
               const std::vector<sim::AgentTruth>& in_view);
  // One perception frame into the world model.
  void Write(std::vector<types::Track> tracks, std::vector<types::Obstacle> obstacles, Stamp stamp);
  std::string mode_;
  Blindness blind_;
  int truth_every_;  // simulator steps per truth frame
  double match_m_;
  world::WorldModel& world_;
  std::optional<sim::SyntheticDetector> detector_;
  std::optional<track::Tracker> tracker_;
  std::unique_ptr<StereoPerception> camera_;
  std::map<std::string, PerceptionCounts> by_class_;
  long frames_ = 0, detections_ = 0;
};

}  // namespace specht::pipeline::internal
