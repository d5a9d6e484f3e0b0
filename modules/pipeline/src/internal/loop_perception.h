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
// Scored by PerceptionScore (an agent in view, camera: as `specht eval perception`
// counts one at its defaults, perception_eval.h).
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

// The simulator's agents as perception would report them, exactly (perception
// truth, and the truth side of the run video): confirmed tracks and obstacles.
void AgentsAsPerceived(const std::vector<sim::AgentTruth>& agents, Stamp stamp, std::vector<types::Track>& tracks,
                       std::vector<types::Obstacle>& obstacles);

// A fault: from at_s (≥ 0) for for_s, perception delivers no frame (a blind camera).
struct Blindness {
  double at_s = -1, for_s = 0;
  bool Covers(double t_s) const { return at_s >= 0 && t_s >= at_s && t_s < at_s + for_s; }
};

// A detector frame's obstacles, each in the car's frame (x ahead and y to the left of
// its box centre, yaw against its heading), placed in the map frame at the believed
// box-centre pose `believed`.
std::vector<types::Obstacle> PlacedAt(std::vector<types::Obstacle> in_car, const sim::Pose2& believed);

// The stack's perception: what the car's sensors deliver, tracked and written into
// the world model. It never reads the simulator: the oracle's agents (mode truth)
// are handed to it like a sensor's frame.
class LoopPerception {
 public:
  LoopPerception(const std::string& mode, const track::TrackerOptions& tracking, world::WorldModel& world,
                 const LoopCameraConfig& camera = {});
  ~LoopPerception();
  const std::string& mode() const { return mode_; }
  // Mode truth: the simulator's agents as confirmed tracks (the oracle's frame).
  std::vector<types::Track> Oracle(const std::vector<sim::AgentTruth>& agents, Stamp stamp);
  // Mode detections: one detector frame, each obstacle in the car's frame (x ahead and
  // y to the left of its box centre, yaw against its heading), placed at the believed
  // box-centre pose `believed`.
  std::vector<types::Track> Detections(std::vector<types::Obstacle> in_car, Stamp stamp, const sim::Pose2& believed);
  // Mode detections with the tracker in a perception node of its own (`specht node
  // perception`): the node's tracks and map-frame obstacles of one frame.
  void Tracked(std::vector<types::Track> tracks, std::vector<types::Obstacle> obstacles, Stamp stamp);
  // Mode camera: one stereo frame, as the simulator's camera delivers it.
  std::vector<types::Track> Camera(const mrpt::obs::CObservationStereoImages& frame, Stamp stamp,
                                   const sim::Pose2& believed);
  nlohmann::json ToJson() const;  // mode, frames, detections

 private:
  // Tracks the frame's obstacles (map frame) and writes both layers.
  std::vector<types::Track> Publish(std::vector<types::Obstacle> obstacles, Stamp stamp);
  // One perception frame into the world model.
  void Write(std::vector<types::Track> tracks, std::vector<types::Obstacle> obstacles, Stamp stamp);
  std::string mode_;
  world::WorldModel& world_;
  std::optional<track::Tracker> tracker_;
  std::unique_ptr<StereoPerception> camera_;
  long frames_ = 0, detections_ = 0, tracked_elsewhere_ = 0;
};

// The referee's score of perception (never fed back): at each perception frame, an
// agent in view counts as found when a reported track lies within match_m of it
// (recall, by the agent's class), and a track is right when an agent lies within
// match_m of it (precision, by the track's class).
class PerceptionScore {
 public:
  explicit PerceptionScore(double match_m) : match_m_(match_m) {}
  void Frame(const std::vector<sim::AgentTruth>& in_view, const std::vector<sim::AgentTruth>& all,
             const std::vector<types::Track>& tracks);
  nlohmann::json ToJson() const;  // match_m, by_class

 private:
  double match_m_;
  std::map<std::string, PerceptionCounts> by_class_;
};

// A detection the simulator made in the map frame, moved into the frame of the car
// at its true box-centre pose `truth` (what the car's own detector would report).
types::Obstacle InCarFrame(types::Obstacle o, const sim::Pose2& truth);

}  // namespace specht::pipeline::internal
