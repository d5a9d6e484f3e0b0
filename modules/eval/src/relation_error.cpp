#include "specht/eval/relation_error.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <queue>

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

// The `count` worst relations seen, kept in a heap with the least bad on top.
class WorstRelations {
 public:
  explicit WorstRelations(size_t count) : count_(count), heap_(&Worse) {}
  void Offer(const Relation& r) {
    if (heap_.size() < count_) {
      heap_.push(r);
    } else if (count_ > 0 && Worse(r, heap_.top())) {
      heap_.pop();
      heap_.push(r);
    }
  }
  std::vector<Relation> TakeWorstFirst() {
    std::vector<Relation> out;
    for (; !heap_.empty(); heap_.pop()) out.push_back(heap_.top());
    std::reverse(out.begin(), out.end());
    return out;
  }

 private:
  size_t count_;
  std::priority_queue<Relation, std::vector<Relation>, decltype(&Worse)> heap_;
};

// ε = δ̂ ⊖ δ*: translational (m) and rotational (deg) size.
std::pair<double, double> RelationErrorOf(const CPose2D& estimated, const CPose2D& reference) {
  const CPose2D e = estimated - reference;
  return {e.norm(), std::abs(mrpt::RAD2DEG(mrpt::math::wrapToPi(e.phi())))};
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
  WorstRelations worst(options.worst_count);
  auto add = [&](size_t i, size_t j, Accumulator& kind) {
    const auto [m, deg] = RelationErrorOf(est[j] - est[i], ref[j] - ref[i]);
    kind.Add(m, deg);
    all.Add(m, deg);
    worst.Offer({i, j, estimate[pairs[i].first].stamp, estimate[pairs[j].first].stamp, &kind == &loop, m, deg});
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
  return RelationError{consecutive.Stats(), loop.Stats(), all.Stats(), n, worst.TakeWorstFirst()};
}

PublishedRelationError ComputePublishedRelationError(const Trajectory& estimate, const io::RelationsFile& file,
                                                     const PublishedRelationOptions& options) {
  const StampLookup lookup(estimate, options.max_dt_s);
  Accumulator absolute, squared;
  WorstRelations worst(options.worst_count);
  size_t unmatched = 0;
  const io::ReferenceRelation* first_unmatched = nullptr;
  Stamp missing;  // first_unmatched's stamp that is not in the estimate
  for (const io::ReferenceRelation& r : file.relations) {
    const auto i = lookup.Find(r.t1), j = lookup.Find(r.t2);
    if (!i || !j) {
      if (!first_unmatched) first_unmatched = &r, missing = i ? r.t2 : r.t1;
      ++unmatched;
      continue;
    }
    const CPose2D a(estimate[*i].pose), b(estimate[*j].pose);
    const auto [m, deg] = RelationErrorOf(b - a, r.delta);
    absolute.Add(m, deg);
    squared.Add(m * m, deg * deg);
    worst.Offer({*i, *j, r.t1, r.t2, false, m, deg});
  }
  if (first_unmatched) {
    char stamp[64];
    std::snprintf(stamp, sizeof stamp, "%.6f", missing.Seconds());
    throw InputError(Where(file.path, static_cast<int>(first_unmatched->line)) + "the relation's stamp " + stamp +
                     " is not in the trajectory (within " + std::to_string(options.max_dt_s * 1e3) + " ms); " +
                     std::to_string(unmatched) + " of " + std::to_string(file.relations.size()) +
                     " relations do not match");
  }
  return PublishedRelationError{absolute.Stats(), squared.Stats(), file.relations.size(), worst.TakeWorstFirst()};
}

nlohmann::json ToJson(const RelationStats& s) {
  return {{"count", s.count},       {"mean_m", s.mean_m},   {"std_m", s.std_m},    {"max_m", s.max_m},
          {"mean_deg", s.mean_deg}, {"std_deg", s.std_deg}, {"max_deg", s.max_deg}};
}

Trajectory RelationSegments(const Trajectory& estimate, const std::vector<Relation>& relations) {
  Trajectory out;
  for (const Relation& r : relations) {
    if (r.i >= estimate.size() || r.j >= estimate.size()) continue;
    out.push_back(estimate[r.i]);
    out.push_back(estimate[r.j]);
  }
  return out;
}

namespace {

nlohmann::json ToJson(const std::vector<Relation>& relations, bool with_kind) {
  nlohmann::json out = nlohmann::json::array();
  for (const Relation& r : relations) {
    out.push_back({{"i", r.i},
                   {"j", r.j},
                   {"t_i", r.stamp_i.Seconds()},
                   {"t_j", r.stamp_j.Seconds()},
                   {"m", r.m},
                   {"deg", r.deg}});
    if (with_kind) out.back()["kind"] = r.loop ? "loop" : "consecutive";
  }
  return out;
}

}  // namespace

nlohmann::json ToJson(const RelationError& e) {
  return {{"consecutive", ToJson(e.consecutive)},
          {"loop", ToJson(e.loop)},
          {"all", ToJson(e.all)},
          {"paired_poses", e.paired_poses},
          {"worst", ToJson(e.worst, true)}};
}

nlohmann::json ToJson(const PublishedRelationError& e) {
  const RelationStats& q = e.squared;
  const nlohmann::json squared = {{"count", q.count},     {"mean_m2", q.mean_m},     {"std_m2", q.std_m},
                                  {"max_m2", q.max_m},    {"mean_deg2", q.mean_deg}, {"std_deg2", q.std_deg},
                                  {"max_deg2", q.max_deg}};
  return {{"relations", e.relations},
          {"absolute", ToJson(e.absolute)},
          {"squared", squared},
          {"worst", ToJson(e.worst, false)}};
}

}  // namespace specht::eval
