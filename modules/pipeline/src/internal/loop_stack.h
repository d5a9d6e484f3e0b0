// The stack the closed loop drives the car with (closed_loop.h): localisation
// (loop_localization.h), perception (loop_perception.h), the world model, the LiDAR
// map, the pose check, the mission state machine with its planners, and the run's
// MCAP. It is fed only what the car delivers — its sensors' observations and
// frames, its own speed and steering angle — and answers each control step with a
// command. The simulator's truth reaches it only as the oracle's inputs of the truth
// modes (OracleEgo, OracleAgents); scoring against the truth is the referee's
// (closed_loop.cpp), never the stack's.
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationStereoImages.h>

#include <memory>
#include <string>
#include <vector>

#include "specht/decide/mission.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/sim/scenario.h"
#include "specht/sim/simulator.h"
#include "specht/types/track.h"
#include "specht/world/world_model.h"

namespace specht::pipeline::internal {

class LoopStack {
 public:
  // Starts the drive at `start` (the simulated clock's zero); figures the stack
  // measures itself (planning, transitions, stage times) go into `result`.
  LoopStack(const sim::Scenario& scenario, uint64_t seed, const std::vector<decide::Goal>& mission,
            const ClosedLoopConfig& config, Stamp start, ClosedLoopResult& result);
  ~LoopStack();

  // The oracle (localization truth): the simulator's box-centre pose now.
  void OracleEgo(const sim::Pose2& truth);
  // The oracle (perception truth): the simulator's agents, one frame; returns the tracks.
  std::vector<types::Track> OracleAgents(const std::vector<sim::AgentTruth>& agents, Stamp stamp);

  // An observation of the car's LiDAR, odometry or IMU, `t_s` into the drive.
  void Observe(Stamp t, double t_s, const mrpt::obs::CObservation::Ptr& observation);
  // A detector frame, each obstacle in the car's frame (loop_perception.h); returns the tracks.
  std::vector<types::Track> Detections(std::vector<types::Obstacle> in_car, Stamp stamp);
  // A detector frame tracked by a perception node of its own: its tracks and
  // map-frame obstacles, placed at Localized() when the frame came.
  void Tracked(std::vector<types::Track> tracks, std::vector<types::Obstacle> obstacles, Stamp stamp);
  // The box-centre pose localisation believes now (map frame): where a detector
  // frame that comes now is placed.
  sim::Pose2 Localized() const;
  // A stereo frame of the car's camera; returns the tracks.
  std::vector<types::Track> Camera(const mrpt::obs::CObservationStereoImages& frame, Stamp stamp);

  // A control step `t_s` into the drive: the car's own speed and steering angle in,
  // the command out.
  plan::Command Control(double t_s, Stamp stamp, double speed_mps, double steer_rad);
  // The drive ran out of time at `t_s`.
  void TimeLimit(double t_s, const std::string& reason);
  bool Final() const;

  // What the latest control step decided on.
  sim::Pose2 Believed() const;  // box centre, map frame
  const world::Snapshot& snapshot() const;
  int tracks_seen() const;
  std::string state() const;
  bool OnLocalPath() const;
  std::vector<plan::Pose> PathAhead() const;  // rear axle, map frame

  // Ends the drive at `end`: closes the MCAP and fills the result's transitions,
  // stack, static layer, localisation and perception summaries and drawn map.
  void Finish(Stamp end);

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace specht::pipeline::internal
