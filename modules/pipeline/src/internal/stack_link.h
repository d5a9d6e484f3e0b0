// How the car side of the closed loop (the simulator and the referee,
// closed_loop.cpp) talks to the stack (loop_stack.h): in this process
// (LocalStackLink), or over DDS with the stack in a process of its own, `specht node
// stack` (DdsStackLink, `specht run --nodes`). Either way the stack gets the same
// inputs in the same order and answers each control step the same.
#pragma once

#include <mrpt/obs/CObservation.h>

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "internal/loop_stack.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/types/obstacle.h"
#include "specht/types/track.h"

namespace specht::pipeline::internal {

// The stack's answer to a control step.
struct StackDecision {
  plan::Command command;
  sim::Pose2 believed;  // box centre, map frame
  std::string state;
  int tracks = 0;
  bool on_local_path = false;
  bool finished = false;  // the mission is over (done or failed)
};

class StackLink {
 public:
  // The tracks perception reported for the frame stamped `stamp` (for the referee).
  using OnTracks = std::function<void(Stamp stamp, const std::vector<types::Track>& tracks)>;
  virtual ~StackLink() = default;
  // An observation of the car's LiDAR, odometry or IMU, `t_s` into the drive.
  virtual void Observe(Stamp t, double t_s, const mrpt::obs::CObservation::Ptr& observation) = 0;
  // A detector frame, each obstacle in the car's frame; its tracks come to OnTracks.
  virtual void Detections(std::vector<types::Obstacle> in_car, Stamp stamp) = 0;
  // The oracle's inputs of the truth modes (loop_stack.h): the simulator's pose of the
  // car, and its agents as a perception frame whose tracks come to OnTracks. Only a
  // stack in this process takes them (`--nodes` runs the full stack only).
  virtual void OracleEgo(const sim::Pose2& truth) = 0;
  virtual void OracleAgents(const std::vector<sim::AgentTruth>& agents, Stamp stamp) = 0;
  // A control step: the car's own speed and steering angle in, the decision out.
  virtual StackDecision Control(double t_s, Stamp stamp, double speed_mps, double steer_rad) = 0;
  // Ends the drive at `end` (`t_s` into it), after a time limit when `time_limit`
  // says why; the stack's figures go into `r` (closed_loop.h: planning, transitions,
  // localisation and perception summaries, the drawn map).
  virtual void Finish(double t_s, Stamp end, const std::string& time_limit, ClosedLoopResult& r) = 0;
  // The stack when it runs in this process (the camera's frames and the video reach
  // it directly), else nullptr.
  virtual LoopStack* local() { return nullptr; }
};

std::unique_ptr<StackLink> LocalStackLink(const sim::Scenario& scenario, uint64_t seed,
                                          const std::vector<decide::Goal>& mission, const ClosedLoopConfig& config,
                                          Stamp start, ClosedLoopResult& r, StackLink::OnTracks on_tracks);

// The stack as `specht node stack`, started for this drive with
// config.stack_node's command (stack_node.cpp).
std::unique_ptr<StackLink> DdsStackLink(const sim::Scenario& scenario, uint64_t seed, const ClosedLoopConfig& config,
                                        ClosedLoopResult& r, StackLink::OnTracks on_tracks);

// The stack's part of a result (what LoopStack writes into it) and back: what the
// stack node hands the run that started it.
nlohmann::json StackFiguresToJson(const ClosedLoopResult& r);
void StackFiguresFromJson(const nlohmann::json& j, ClosedLoopResult& r);

}  // namespace specht::pipeline::internal
