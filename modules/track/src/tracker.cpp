#include "specht/track/tracker.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "internal/motion_filter.h"
#include "specht/core/assignment.h"
#include "specht/core/error.h"

namespace specht::track {

using internal::Mat2;
using internal::Mat4;
using internal::MotionFilter;
using internal::Vec2;
using internal::Vec4;

namespace {

// "class=σ" entries, later entries of a class winning.
std::map<std::string, double> ParseNoise(const std::vector<std::string>& entries, std::vector<std::string>* problems) {
  std::map<std::string, double> out;
  for (const auto& [cls, sigma] : params::ParseNumberAssignments(
           entries, "acceleration_noise", [](double v) { return v > 0 && std::isfinite(v); },
           "a positive number (m/s²)", problems))
    out[cls] = sigma;
  return out;
}

// χ²(2) quantile: for two degrees of freedom the CDF is 1 − exp(−d²/2).
double ChiSquare2Quantile(double p) { return -2.0 * std::log(1.0 - p); }

Mat2 ToEigen(const cv::Matx22d& m) {
  Mat2 out;
  out << m(0, 0), m(0, 1), m(1, 0), m(1, 1);
  return out;
}

cv::Matx22d ToCv(const Mat2& m) { return {m(0, 0), m(0, 1), m(1, 0), m(1, 1)}; }

}  // namespace

std::vector<std::string> TrackerOptions::Relations() const {
  std::vector<std::string> problems;
  const auto noise = ParseNoise(acceleration_noise, &problems);
  if (problems.empty() && !noise.count("other"))
    problems.push_back("acceleration_noise: needs an \"other=σ\" entry for classes not listed");
  if (confirm_hits > confirm_window) problems.push_back("confirm_hits must not exceed confirm_window");
  return problems;
}

bool TrackerOptions::UsesTurnModel(const std::string& cls) const {
  if (motion_model != "auto") return motion_model == "ct";
  return cls == "car" || cls == "cyclist" || cls == "truck" || cls == "bus";
}

struct Tracker::Entry {
  long id = 0;
  TrackState state = TrackState::kTentative;
  std::unique_ptr<MotionFilter> filter;
  std::map<std::string, double> votes;
  std::string cls;
  double length_m = 0, width_m = 0, yaw_rad = 0;  // the latest detection's box
  Stamp last_seen;
  int cycles = 0, hits = 0;
  std::deque<types::TrackPoint> history;

  void Vote(const types::Obstacle& d) {
    votes[d.cls] += std::max(d.score, 1e-3);
    cls = std::max_element(votes.begin(), votes.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
    const bool box = d.length_m > 0 && d.width_m > 0;
    length_m = box ? d.length_m : 2 * d.radius_m, width_m = box ? d.width_m : 2 * d.radius_m;
    yaw_rad = box ? d.yaw_rad : 0;
  }
};

Tracker::Tracker(const TrackerOptions& options) : options_(options) {
  const auto problems = options.Relations();
  if (!problems.empty()) throw InputError("track: " + problems.front());
  acceleration_noise_ = ParseNoise(options.acceleration_noise, nullptr);
  gate_d2_ = ChiSquare2Quantile(options.gate_probability);
}
Tracker::~Tracker() = default;

double Tracker::AccelerationSigma(const std::string& cls) const {
  const auto it = acceleration_noise_.find(cls);
  return it != acceleration_noise_.end() ? it->second : acceleration_noise_.at("other");
}
Tracker::Tracker(Tracker&&) noexcept = default;
Tracker& Tracker::operator=(Tracker&&) noexcept = default;

CycleStats Tracker::Update(const std::vector<types::Obstacle>& detections_in, Stamp now) {
  if (started_ && now < last_)
    throw InputError("track: detections at " + std::to_string(now.Seconds()) + " s are older than the last cycle (" +
                     std::to_string(last_.Seconds()) + " s)");
  const double dt = started_ ? SecondsBetween(last_, now) : 0.0;
  started_ = true;
  last_ = now;
  CycleStats stats;

  std::vector<const types::Obstacle*> detections;
  for (const auto& d : detections_in) {
    const bool finite = std::isfinite(d.x_m) && std::isfinite(d.y_m) && std::isfinite(d.covariance_xy(0, 0)) &&
                        std::isfinite(d.covariance_xy(1, 1)) && std::isfinite(d.covariance_xy(0, 1));
    if (finite)
      detections.push_back(&d);
    else
      ++skipped_;
  }
  stats.detections = static_cast<int>(detections.size());
  // Each detection's covariance, symmetrised, with the floor added.
  const double floor2 = options_.min_measurement_sigma_m * options_.min_measurement_sigma_m;
  std::vector<Mat2> measurement_cov(detections.size());
  for (size_t k = 0; k < detections.size(); ++k) {
    const Mat2 r = ToEigen(detections[k]->covariance_xy);
    measurement_cov[k] = (r + r.transpose()) / 2 + Mat2::Identity() * floor2;
  }

  // 1. Predict.
  for (auto& t : tracks_) {
    if (dt > 0) t->filter->Predict(dt, AccelerationSigma(t->cls), options_.turn_noise_rad_s2);
    ++t->cycles;
  }

  // 2–3. Gate and assign on the negative log likelihood.
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::vector<double>> cost(tracks_.size(), std::vector<double>(detections.size(), inf));
  for (size_t i = 0; i < tracks_.size(); ++i) {
    const Vec2 p = tracks_[i]->filter->Position();
    const Mat2 pp = tracks_[i]->filter->PositionCovariance();
    for (size_t k = 0; k < detections.size(); ++k) {
      const Vec2 nu = Vec2(detections[k]->x_m, detections[k]->y_m) - p;
      const Mat2 s = pp + measurement_cov[k];
      const double d2 = nu.dot(s.ldlt().solve(nu));
      if (!(d2 <= gate_d2_)) continue;
      cost[i][k] = d2 + std::log(s.determinant());
      ++stats.gated_pairs;
    }
  }
  const Assignment assignment = SolveAssignment(cost);

  // 4. Update, lifecycle.
  // A detection starts no track when it updated one, or when it lies inside a
  // confirmed track's gate: then it is the same object seen twice, or clutter beside it.
  std::vector<char> claimed(detections.size(), 0);
  for (size_t i = 0; i < tracks_.size(); ++i)
    if (tracks_[i]->state != TrackState::kTentative)
      for (size_t k = 0; k < detections.size(); ++k) claimed[k] |= std::isfinite(cost[i][k]);
  for (size_t i = 0; i < tracks_.size(); ++i) {
    Entry& t = *tracks_[i];
    const int k = assignment.column_of_row[i];
    if (k >= 0) {
      claimed[k] = 1;
      ++stats.assigned;
      const auto& d = *detections[k];
      t.filter->Update(Vec2(d.x_m, d.y_m), measurement_cov[k]);
      t.Vote(d);
      t.last_seen = now;
      ++t.hits;
      if (t.state == TrackState::kCoasting) t.state = TrackState::kConfirmed;
      if (t.state == TrackState::kTentative && t.hits >= options_.confirm_hits) {
        t.state = TrackState::kConfirmed;
        ++stats.confirmed;
        if (options_.UsesTurnModel(t.cls))
          t.filter = internal::MakeConstantTurn(*t.filter, options_.initial_turn_rate_sigma_rad_s);
      }
    } else if (t.state == TrackState::kConfirmed) {
      t.state = TrackState::kCoasting;
    }
    const Vec2 p = t.filter->Position();
    t.history.push_back({now, p.x(), p.y()});
    while (static_cast<int>(t.history.size()) > options_.history_length) t.history.pop_front();
  }
  const auto erased = std::remove_if(tracks_.begin(), tracks_.end(), [&](const std::unique_ptr<Entry>& t) {
    // A tentative track lives while it can still reach confirm_hits within its
    // window: a miss does not end it (one missed frame of a 0.7-probability detector
    // would otherwise restart the count of a road user beside the car).
    if (t->state == TrackState::kTentative)
      return t->hits + (options_.confirm_window - t->cycles) < options_.confirm_hits;
    return SecondsBetween(t->last_seen, now) > options_.coast_timeout_s;
  });
  stats.deleted = static_cast<int>(tracks_.end() - erased);
  tracks_.erase(erased, tracks_.end());

  for (size_t k = 0; k < detections.size(); ++k) {
    if (claimed[k]) continue;
    const auto& d = *detections[k];
    auto t = std::make_unique<Entry>();
    t->id = next_id_++;
    t->filter =
        internal::MakeConstantVelocity(Vec2(d.x_m, d.y_m), measurement_cov[k], options_.initial_speed_sigma_mps);
    t->Vote(d);
    t->last_seen = now;
    t->hits = 1;
    t->history.push_back({now, d.x_m, d.y_m});
    if (options_.confirm_hits <= 1) t->state = TrackState::kConfirmed;
    tracks_.push_back(std::move(t));
    ++stats.born;
  }
  return stats;
}

std::vector<types::Track> Tracker::Tracks() const {
  std::vector<types::Track> out;
  for (const auto& t : tracks_) {
    if (t->state == TrackState::kTentative) continue;
    if (t->state == TrackState::kCoasting && SecondsBetween(t->last_seen, last_) > options_.report_coasting_s) continue;
    types::Track w;
    w.id = t->id;
    w.cls = t->cls;
    w.stamp = last_;
    Vec4 x;
    Mat4 p;
    t->filter->Cartesian(x, p);
    w.x_m = x(0), w.y_m = x(1), w.vx_mps = x(2), w.vy_mps = x(3);
    w.length_m = t->length_m, w.width_m = t->width_m, w.yaw_rad = t->yaw_rad;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) w.covariance(r, c) = p(r, c);
    w.state = t->state == TrackState::kConfirmed ? "confirmed" : "coasting";
    w.motion_model = t->filter->name();
    w.history.assign(t->history.begin(), t->history.end());
    if (options_.prediction_horizon_s > 0) {
      auto f = t->filter->Clone();
      const double sigma_a = AccelerationSigma(t->cls);
      for (double ahead = options_.prediction_step_s; ahead <= options_.prediction_horizon_s + 1e-9;
           ahead += options_.prediction_step_s) {
        f->Predict(options_.prediction_step_s, sigma_a, options_.turn_noise_rad_s2);
        const Vec2 q = f->Position();
        w.prediction.push_back({ahead, q.x(), q.y(), ToCv(f->PositionCovariance())});
      }
    }
    out.push_back(std::move(w));
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  return out;
}

int Tracker::tentative_count() const {
  return static_cast<int>(
      std::count_if(tracks_.begin(), tracks_.end(), [](const auto& t) { return t->state == TrackState::kTentative; }));
}

}  // namespace specht::track
