// specht/sim/detections.h: noisy obstacle detections of the simulator's
// agents, standing in for the stereo + CNN pipeline when tracking and classification
// are evaluated on synthetic scenes (the truth is the simulator's).
//
// An agent is detectable when it is within range_m of the ego and the line from the
// ego to its centre is not blocked by the static world (agents do not occlude each
// other). A detectable agent is detected with probability detection_probability; its
// position gets isotropic Gaussian noise σ = position_sigma_m + range_sigma_fraction
// · distance, reported as the detection's covariance; with probability class_error
// its class is replaced by another. False alarms arrive as a Poisson number per frame
// (mean false_alarms_per_frame), uniform in the range disc where it is not blocked.
// For scoring, an agent that was out of view longer than truth_episode_gap_s comes
// back under a new truth id ("<agent>#<episode>"): a tracker without appearance
// cannot re-identify it, so CLEAR MOT would count every return as an ID switch. The
// default equals the tracker's coast_timeout_s: how long it promises to remember.
#pragma once

#include <random>
#include <vector>

#include "specht/core/params.h"
#include "specht/sim/simulator.h"
#include "specht/types/obstacle.h"

namespace specht::sim {

// Section "synthetic_detections".
struct SyntheticDetectionOptions {
  double rate_hz = 10;
  double range_m = 30;
  double detection_probability = 0.9;
  double position_sigma_m = 0.15;
  double range_sigma_fraction = 0.01;
  double class_error = 0.05;
  double false_alarms_per_frame = 0.2;
  double truth_episode_gap_s = 3.0;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("rate_hz", rate_hz, "detection frames per second", Range::Of(0.5, 100.0));
    v.Param("range_m", range_m, "agents beyond this distance from the ego are not seen", Range::Of(1.0, 200.0));
    v.Param("detection_probability", detection_probability, "chance a visible agent is detected in a frame",
            Range::Of(0.0, 1.0));
    v.Param("position_sigma_m", position_sigma_m, "position noise σ at zero range", Range::Of(0.0, 5.0));
    v.Param("range_sigma_fraction", range_sigma_fraction, "position noise σ growth per metre of range",
            Range::Of(0.0, 0.5));
    v.Param("class_error", class_error, "chance a detection carries a wrong class", Range::Of(0.0, 1.0));
    v.Param("false_alarms_per_frame", false_alarms_per_frame, "mean false detections per frame", Range::Of(0.0, 50.0));
    v.Param("truth_episode_gap_s", truth_episode_gap_s,
            "an agent out of view this long comes back under a new truth id (no re-identification)",
            Range::Of(0.0, 1e6));
  }
};

class SyntheticDetector {
 public:
  SyntheticDetector(const SyntheticDetectionOptions& options, uint64_t seed);
  // Whether a detection frame is due after the simulator's latest step.
  bool Due(const Simulator& sim) const;
  // The detections of the simulator's current state (map frame, stamped now).
  std::vector<types::Obstacle> Detect(const Simulator& sim);
  // The agents that were detectable in the last frame (the truth to score against),
  // and the others (present but out of view: don't care).
  const std::vector<AgentTruth>& visible() const { return visible_; }
  const std::vector<AgentTruth>& hidden() const { return hidden_; }

 private:
  SyntheticDetectionOptions options_;
  std::mt19937_64 rng_;
  std::vector<AgentTruth> visible_, hidden_;
  long next_id_ = 1;
};

}  // namespace specht::sim
