// specht/track/tracker.h: multi-object tracking of obstacles in the map frame.
//
// Each cycle (one set of detections at one time):
//   1. every track is predicted to the detections' stamp by its motion model:
//        cv  constant velocity, state (x, y, vx, vy), linear Kalman filter,
//            white-noise acceleration σ_a:  Q = σ_a² G Gᵀ,  G = [dt²/2 I; dt I]
//        ct  constant turn rate and velocity, state (x, y, v, θ, ω), extended KF:
//              x' = x + v/ω (sin(θ + ω dt) − sin θ),  y' = y − v/ω (cos(θ + ω dt) − cos θ)
//              (the straight-line limit for |ω| → 0), θ' = θ + ω dt
//            noise on v (σ_a) and ω (σ_ω, rad/s²) entering through G.
//      Tracks start as cv (a heading is unknown from one detection) and switch to ct
//      when confirmed, if their class uses ct (motion_model: auto → car, cyclist,
//      truck, bus; or ct/cv for every class).
//   2. gating: a detection z may go to a track only if its squared Mahalanobis
//      distance d² = νᵀ S⁻¹ ν (ν = z − H x̂, S = H P Hᵀ + R) is within the χ²(2)
//      quantile of gate_probability;
//   3. optimal assignment (Hungarian, core/assignment.h) minimising the negative
//      log likelihood d² + ln det S over the gated pairs;
//   4. lifecycle: a new detection starts a tentative track; it is confirmed after
//      confirm_hits hits within its first confirm_window cycles (M of N: misses
//      allowed), deleted once it can no longer reach them. A
//      confirmed track missed in a cycle is coasting; seen again it is confirmed;
//      unseen for coast_timeout_s it is deleted. Confirmed tracks and coasting
//      tracks unseen for at most report_coasting_s are reported; longer coasting
//      ones are only kept to re-associate (an agent behind a parked car).
// The class of a track is the score-weighted vote of its detections' classes; its
// process noise is the class's (acceleration_noise, "class=σ_a").
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/time.h"
#include "specht/types/obstacle.h"
#include "specht/types/track.h"

namespace specht::track {

// Section "track".
struct TrackerOptions {
  std::string motion_model = "cv";
  std::vector<std::string> acceleration_noise = {"pedestrian=1.5", "cyclist=2.0", "car=2.5", "other=2.0"};
  double turn_noise_rad_s2 = 0.8;
  double gate_probability = 0.9999;
  double min_measurement_sigma_m = 0.05;
  double initial_speed_sigma_mps = 5.0;
  double initial_turn_rate_sigma_rad_s = 0.5;
  int confirm_hits = 3;
  int confirm_window = 5;
  double coast_timeout_s = 3.0;
  double report_coasting_s = 0.5;
  int history_length = 300;
  double prediction_horizon_s = 3.0;
  double prediction_step_s = 0.5;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("motion_model", motion_model, {"auto", "cv", "ct"},
             "cv everywhere, ct everywhere, or auto: ct for car, cyclist, truck and bus");
    v.Param("acceleration_noise", acceleration_noise, "white-noise acceleration σ (m/s²) per class, \"class=σ\"");
    v.Param("turn_noise_rad_s2", turn_noise_rad_s2, "ct model: yaw acceleration σ", Range::Of(0.01, 10.0).Log());
    v.Param("gate_probability", gate_probability, "χ²(2) gate on the Mahalanobis distance", Range::Of(0.5, 0.99999));
    v.Param("min_measurement_sigma_m", min_measurement_sigma_m, "floor on a detection's position σ",
            Range::Of(0.0, 2.0));
    v.Param("initial_speed_sigma_mps", initial_speed_sigma_mps, "σ of the unknown speed of a new track",
            Range::Of(0.1, 30.0));
    v.Param("initial_turn_rate_sigma_rad_s", initial_turn_rate_sigma_rad_s,
            "σ of the turn rate when a track switches to ct", Range::Of(0.01, 5.0));
    v.Param("confirm_hits", confirm_hits, "hits that confirm a tentative track", Range::Of(1, 20));
    v.Param("confirm_window", confirm_window, "…within this many cycles of its birth", Range::Of(1, 50));
    v.Param("coast_timeout_s", coast_timeout_s, "a track unseen this long is deleted", Range::Of(0.05, 30.0).Log());
    v.Param("report_coasting_s", report_coasting_s,
            "coasting tracks unseen longer are kept for re-association but not reported", Range::Of(0.0, 30.0));
    v.Param("history_length", history_length, "positions kept per track", Range::Of(1, 100000));
    v.Param("prediction_horizon_s", prediction_horizon_s, "how far ahead tracks are predicted", Range::Of(0.0, 30.0));
    v.Param("prediction_step_s", prediction_step_s, "spacing of the predicted points", Range::Of(0.05, 10.0));
  }
  std::vector<std::string> Relations() const;
  bool UsesTurnModel(const std::string& cls) const;
};

enum class TrackState { kTentative, kConfirmed, kCoasting };

// Counts of one cycle (for logs and reports).
struct CycleStats {
  int detections = 0, gated_pairs = 0, assigned = 0, born = 0, confirmed = 0, deleted = 0;
};

class Tracker {
 public:
  explicit Tracker(const TrackerOptions& options);  // throws InputError on bad options
  ~Tracker();
  Tracker(Tracker&&) noexcept;
  Tracker& operator=(Tracker&&) noexcept;

  // One cycle with the detections made at `now` (their own stamps are ignored;
  // stamps must not decrease: InputError otherwise). Detections with non-finite
  // positions are skipped and counted.
  CycleStats Update(const std::vector<types::Obstacle>& detections, Stamp now);

  // Confirmed and coasting tracks at the last cycle, with history and prediction,
  // ordered by id.
  std::vector<types::Track> Tracks() const;
  int tentative_count() const;
  long skipped_detections() const { return skipped_; }

 private:
  struct Entry;
  double AccelerationSigma(const std::string& cls) const;  // the class's, else "other"'s
  TrackerOptions options_;
  std::map<std::string, double> acceleration_noise_;
  double gate_d2_ = 0;
  std::vector<std::unique_ptr<Entry>> tracks_;
  long next_id_ = 1;
  long skipped_ = 0;
  bool started_ = false;
  Stamp last_;
};

}  // namespace specht::track
