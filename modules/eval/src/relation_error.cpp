#include "specht/eval/relation_error.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include "specht/core/error.h"
#include "specht/eval/trajectory_error.h"

namespace specht::eval {
namespace {

using mrpt::poses::CPose2D;

// Accumulates mean, std and max of translational and rotational errors.
class Accumulator {
 public:
  void Add(double m, double deg) {
    ++n_;
    sum_m_ += m, sum2_m_ += m * m, max_m_ = std::max(max_m_, m);
    sum_d_ += deg, sum2_d_ += deg * deg, max_d_ = std::max(max_d_, deg);
  }
  RelationStats Stats() const {
    RelationStats s;
    s.count = n_;
    if (n_ == 0) return s;
    const double n = static_cast<double>(n_);
    s.mean_m = sum_m_ / n, s.max_m = max_m_;
    s.std_m = std::sqrt(std::max(0.0, sum2_m_ / n - s.mean_m * s.mean_m));
    s.mean_deg = sum_d_ / n, s.max_deg = max_d_;
    s.std_deg = std::sqrt(std::max(0.0, sum2_d_ / n - s.mean_deg * s.mean_deg));
    return s;
  }

 private:
  size_t n_ = 0;
  double sum_m_ = 0, sum2_m_ = 0, max_m_ = 0, sum_d_ = 0, sum2_d_ = 0, max_d_ = 0;
};

// Larger translational error first; ties in index order.
bool Worse(const Relation& a, const Relation& b) {
  if (a.m != b.m) return a.m > b.m;
  return a.i != b.i ? a.i < b.i : a.j < b.j;
}

}  // namespace

RelationError ComputeRelationError(const Trajectory& estimate, const Trajectory& reference,
                                   const RelationOptions& options) {
  const auto pairs = AssociateByTime(estimate, reference, options.max_dt_s);
  if (pairs.size() < 2) {
    throw InputError("relation error: only " + std::to_string(pairs.size()) + " poses pair up by time stamp");
  }
  std::vector<CPose2D> est, ref;
  for (const auto& [i, j] : pairs) {
    est.emplace_back(estimate[i].pose);
    ref.emplace_back(reference[j].pose);
  }
  Accumulator consecutive, loop, all;
  // The worst_count worst so far, the least bad on top.
  std::priority_queue<Relation, std::vector<Relation>, decltype(&Worse)> worst(&Worse);
  auto add = [&](size_t i, size_t j, Accumulator& kind) {
    const CPose2D e = (est[j] - est[i]) - (ref[j] - ref[i]);
    const double m = e.norm(), deg = std::abs(mrpt::RAD2DEG(mrpt::math::wrapToPi(e.phi())));
    kind.Add(m, deg);
    all.Add(m, deg);
    const Relation r{i, j, estimate[pairs[i].first].stamp, estimate[pairs[j].first].stamp, &kind == &loop, m, deg};
    if (worst.size() < options.worst_count) {
      worst.push(r);
    } else if (options.worst_count > 0 && Worse(r, worst.top())) {
      worst.pop();
      worst.push(r);
    }
  };
  const size_t n = est.size();
  for (size_t i = 0; i + 1 < n; ++i) add(i, i + 1, consecutive);
  const double r2 = options.loop_max_distance_m * options.loop_max_distance_m;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + options.loop_min_separation + 1; j < n; ++j) {
      const double dx = ref[i].x() - ref[j].x(), dy = ref[i].y() - ref[j].y();
      if (dx * dx + dy * dy <= r2) add(i, j, loop);
    }
  }
  RelationError result{consecutive.Stats(), loop.Stats(), all.Stats(), n, {}};
  for (; !worst.empty(); worst.pop()) result.worst.push_back(worst.top());
  std::reverse(result.worst.begin(), result.worst.end());
  return result;
}

nlohmann::json ToJson(const RelationStats& s) {
  return {{"count", s.count}, {"mean_m", s.mean_m}, {"std_m", s.std_m}, {"max_m", s.max_m},
          {"mean_deg", s.mean_deg}, {"std_deg", s.std_deg}, {"max_deg", s.max_deg}};
}

nlohmann::json ToJson(const RelationError& e) {
  nlohmann::json worst = nlohmann::json::array();
  for (const Relation& r : e.worst) {
    worst.push_back({{"i", r.i}, {"j", r.j}, {"t_i", r.stamp_i.Seconds()}, {"t_j", r.stamp_j.Seconds()},
                     {"kind", r.loop ? "loop" : "consecutive"}, {"m", r.m}, {"deg", r.deg}});
  }
  return {{"consecutive", ToJson(e.consecutive)}, {"loop", ToJson(e.loop)}, {"all", ToJson(e.all)},
          {"paired_poses", e.paired_poses}, {"worst", worst}};
}

}  // namespace specht::eval
