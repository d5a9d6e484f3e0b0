#include "specht/eval/trajectory_error.h"

#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "specht/core/error.h"

namespace specht::eval {

StampLookup::StampLookup(const Trajectory& trajectory, double max_dt_s)
    : trajectory_(trajectory), by_stamp_(trajectory.size()), max_dt_ns_(static_cast<int64_t>(max_dt_s * 1e9)) {
  std::iota(by_stamp_.begin(), by_stamp_.end(), size_t{0});
  std::stable_sort(by_stamp_.begin(), by_stamp_.end(),
                   [&](size_t a, size_t b) { return trajectory_[a].stamp < trajectory_[b].stamp; });
}

std::optional<size_t> StampLookup::Find(Stamp t) const {
  auto it = std::lower_bound(by_stamp_.begin(), by_stamp_.end(), t,
                             [&](size_t k, Stamp s) { return trajectory_[k].stamp < s; });
  std::optional<size_t> best;
  int64_t best_dt = max_dt_ns_ + 1;
  for (auto c : {it, it == by_stamp_.begin() ? it : it - 1}) {
    if (c == by_stamp_.end()) continue;
    const int64_t dt = std::llabs(trajectory_[*c].stamp.ns - t.ns);
    if (dt < best_dt) best_dt = dt, best = *c;
  }
  return best;
}

std::vector<std::pair<size_t, size_t>> AssociateByTime(const Trajectory& estimate, const Trajectory& reference,
                                                       double max_dt_s) {
  std::vector<std::pair<size_t, size_t>> pairs;
  const StampLookup lookup(reference, max_dt_s);
  for (size_t i = 0; i < estimate.size(); ++i) {
    if (auto j = lookup.Find(estimate[i].stamp)) pairs.emplace_back(i, *j);
  }
  return pairs;
}

AteResult AbsoluteTrajectoryError2D(const Trajectory& estimate, const Trajectory& reference, double max_dt_s) {
  const auto pairs = AssociateByTime(estimate, reference, max_dt_s);
  if (pairs.size() < 2) {
    throw InputError("trajectory error: only " + std::to_string(pairs.size()) +
                     " poses pair up by time stamp (within " + std::to_string(max_dt_s) + " s)");
  }
  double px = 0, py = 0, qx = 0, qy = 0;
  for (const auto& [i, j] : pairs) {
    px += estimate[i].pose.x(), py += estimate[i].pose.y();
    qx += reference[j].pose.x(), qy += reference[j].pose.y();
  }
  const double n = static_cast<double>(pairs.size());
  px /= n, py /= n, qx /= n, qy /= n;
  double cross = 0, dot = 0;
  for (const auto& [i, j] : pairs) {
    const double ax = estimate[i].pose.x() - px, ay = estimate[i].pose.y() - py;
    const double bx = reference[j].pose.x() - qx, by = reference[j].pose.y() - qy;
    cross += ax * by - ay * bx;
    dot += ax * bx + ay * by;
  }
  const double theta = std::atan2(cross, dot);
  const double c = std::cos(theta), s = std::sin(theta);
  AteResult r;
  r.pairs = pairs.size();
  r.alignment = mrpt::poses::CPose2D(qx - (c * px - s * py), qy - (s * px + c * py), theta);
  double sum2 = 0, sum = 0, sum2_deg = 0;
  for (const auto& [i, j] : pairs) {
    const double x = c * estimate[i].pose.x() - s * estimate[i].pose.y() + r.alignment.x();
    const double y = s * estimate[i].pose.x() + c * estimate[i].pose.y() + r.alignment.y();
    const double e = std::hypot(x - reference[j].pose.x(), y - reference[j].pose.y());
    const double e_deg =
        std::abs(mrpt::RAD2DEG(mrpt::math::wrapToPi(estimate[i].pose.yaw() + theta - reference[j].pose.yaw())));
    sum += e, sum2 += e * e, sum2_deg += e_deg * e_deg;
    r.max_m = std::max(r.max_m, e);
    r.max_deg = std::max(r.max_deg, e_deg);
    r.final_error_m = e;
  }
  r.mean_m = sum / n;
  r.rmse_m = std::sqrt(sum2 / n);
  r.rmse_deg = std::sqrt(sum2_deg / n);
  return r;
}

nlohmann::json ToJson(const AteResult& a) {
  return {{"pairs", a.pairs}, {"rmse_m", a.rmse_m},     {"mean_m", a.mean_m},
          {"max_m", a.max_m}, {"rmse_deg", a.rmse_deg}, {"final_m", a.final_error_m}};
}

Trajectory Transform(const Trajectory& t, const mrpt::poses::CPose2D& alignment) {
  Trajectory out = t;
  const mrpt::poses::CPose3D a(alignment);
  for (auto& p : out) p.pose = a + p.pose;
  return out;
}

}  // namespace specht::eval
