// specht/eval/trajectory_error.h: trajectory accuracy against a reference.
//
// Absolute trajectory error (ATE) in 2D: estimate and reference poses are paired by
// time stamp (nearest within max_dt_s), the estimate is aligned to the reference by
// the rigid SE(2) transform that minimises the squared position error (closed form,
// Umeyama without scale):
//   p̄, q̄ = centroids of estimate positions p_i and reference positions q_i
//   θ* = atan2(Σ (p_i−p̄) × (q_i−q̄), Σ (p_i−p̄) · (q_i−q̄)),  t* = q̄ − R(θ*) p̄
// and the errors |R(θ*) p_i + t* − q_i| and |wrap(φ_i + θ* − ψ_i)| are summarised.
#pragma once

#include <mrpt/poses/CPose2D.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "specht/core/trajectory.h"

namespace specht::eval {

struct AteResult {
  size_t pairs = 0;
  double rmse_m = 0, mean_m = 0, max_m = 0;
  double rmse_deg = 0, max_deg = 0;
  double final_error_m = 0;        // at the last pair, after alignment
  mrpt::poses::CPose2D alignment;  // reference_from_estimate
};

// The pose of a trajectory nearest a stamp, within max_dt_s; the trajectory's stamps
// need not increase (a log's may go backwards). Keeps a reference to `trajectory`.
class StampLookup {
 public:
  StampLookup(const Trajectory& trajectory, double max_dt_s);
  std::optional<size_t> Find(Stamp t) const;

 private:
  const Trajectory& trajectory_;
  std::vector<size_t> by_stamp_;  // indices in stamp order
  int64_t max_dt_ns_;
};

// Pairs of indices (estimate, reference) whose stamps differ by at most max_dt_s.
std::vector<std::pair<size_t, size_t>> AssociateByTime(const Trajectory& estimate, const Trajectory& reference,
                                                       double max_dt_s);

// Throws InputError when fewer than 2 poses pair up.
AteResult AbsoluteTrajectoryError2D(const Trajectory& estimate, const Trajectory& reference, double max_dt_s);

// For reports: {pairs, rmse_m, mean_m, max_m, rmse_deg, final_m}.
nlohmann::json ToJson(const AteResult& ate);

// The estimate moved into the reference frame by `alignment` (for plots).
Trajectory Transform(const Trajectory& t, const mrpt::poses::CPose2D& alignment);

}  // namespace specht::eval
