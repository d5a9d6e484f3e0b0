#include "specht/classify/preprocess.h"

#include <algorithm>
#include <cmath>

#include "specht/core/error.h"

namespace specht::classify {
namespace {

double Clamp01(double v) { return std::min(1.0, std::max(0.0, v)); }

void CheckPoints(const Trajectory& t) {
  for (size_t i = 0; i < t.points.size(); ++i) {
    const auto& p = t.points[i];
    if (!std::isfinite(p.t_s) || !std::isfinite(p.x) || !std::isfinite(p.y))
      throw InputError("trajectory " + t.object_id + ": sample " + std::to_string(i) + " has a non-finite value");
    if (i > 0 && p.t_s < t.points[i - 1].t_s)
      throw InputError("trajectory " + t.object_id + ": sample " + std::to_string(i) + " goes back in time (" +
                       std::to_string(p.t_s) + " s after " + std::to_string(t.points[i - 1].t_s) + " s)");
  }
}

}  // namespace

const std::vector<std::string>& FeatureNames() {
  static const std::vector<std::string> names = {"x",        "y",        "dt",        "speed",       "course",
                                                 "heading",  "accel",    "turn_rate", "dist_static", "dist_poi",
                                                 "region_x", "region_y", "category"};
  return names;
}

int FeatureRows(const PreprocessOptions& o) {
  int rows = 0;
  for (const auto& f : o.features) rows += f == "category" ? 1 + 2 * o.category_frequencies : f == "heading" ? 2 : 1;
  return rows;
}

std::vector<std::string> PreprocessOptions::Relations() const {
  std::vector<std::string> problems;
  if (features.empty()) problems.push_back("features: at least one");
  for (const auto& f : features)
    if (std::find(FeatureNames().begin(), FeatureNames().end(), f) == FeatureNames().end())
      problems.push_back("features: unknown feature \"" + f + "\"");
  for (const auto& f : log_scaled)
    if (f != "dt" && f != "dist_static" && f != "dist_poi")
      problems.push_back("log_scaled: \"" + f + "\" cannot be log-scaled (dt, dist_static, dist_poi can)");
  return problems;
}

std::vector<Trajectory> Split(const Trajectory& t, const PreprocessOptions& o) {
  CheckPoints(t);
  std::vector<Trajectory> out;
  for (size_t i = 0; i < t.points.size(); ++i) {
    bool cut = i == 0;
    if (!cut) {
      const double dt = t.points[i].t_s - t.points[i - 1].t_s;
      const double d2 = std::pow(t.points[i].x - t.points[i - 1].x, 2) + std::pow(t.points[i].y - t.points[i - 1].y, 2);
      cut = dt > o.max_gap_s ||
            (d2 > o.max_jump_sq && (o.max_jump_speed <= 0 || d2 > std::pow(o.max_jump_speed * dt, 2)));
    }
    if (cut) out.push_back({t.object_id, t.label, {}, t.category});
    out.back().points.push_back(t.points[i]);
  }
  return out;
}

std::vector<Window> Chunk(const Trajectory& t, const PreprocessOptions& o) {
  std::vector<Window> out;
  const size_t n = static_cast<size_t>(o.length);
  for (size_t start = 0; start < t.points.size(); start += n) {
    const size_t count = std::min(n, t.points.size() - start);
    if (count < n && count < o.min_fill * n) break;  // the leftover is too short
    Window w;
    w.object_id = t.object_id;
    w.label = t.label;
    w.category = t.category;
    w.t0_s = t.points[start].t_s;
    w.valid = static_cast<int>(count);
    w.points.assign(t.points.begin() + start, t.points.begin() + start + count);
    out.push_back(std::move(w));
  }
  return out;
}

double MeanStepLength(const std::vector<TrajectoryPoint>& p) {
  if (p.size() < 2) return 0;
  double sum = 0;
  for (size_t i = 1; i < p.size(); ++i) sum += std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
  return sum / static_cast<double>(p.size());  // the paper's α divides by n
}

std::vector<Window> MakeWindows(const std::vector<Trajectory>& trajectories, const PreprocessOptions& o,
                                std::map<std::string, std::map<std::string, long>>* counts) {
  std::vector<Window> out;
  auto count = [&](const char* step, const std::string& label) {
    if (counts) ++(*counts)[step][label];
  };
  for (const auto& t : trajectories) {
    count("input", t.label);
    for (const auto& piece : Split(t, o)) {
      count("split", piece.label);
      for (auto& w : Chunk(piece, o)) {
        count("chunked", w.label);
        if (MeanStepLength(w.points) < o.stationary_threshold) continue;
        count("moving", w.label);
        out.push_back(std::move(w));
      }
    }
  }
  return out;
}

void RelativeToFirst(std::vector<TrajectoryPoint>& p) {
  if (p.empty()) return;
  const double x0 = p[0].x, y0 = p[0].y;
  for (auto& q : p) q.x -= x0, q.y -= y0;
}

void RotateToZero(std::vector<TrajectoryPoint>& p) {
  if (p.empty()) return;
  const double a = -std::atan2(p.back().y, p.back().x);
  if (p.back().x == 0 && p.back().y == 0) return;  // a round trip: no direction to align
  const double c = std::cos(a), s = std::sin(a);
  for (auto& q : p) {
    const double x = c * q.x - s * q.y, y = s * q.x + c * q.y;
    q.x = x, q.y = y;
  }
}

namespace {
std::vector<TrajectoryPoint> Transformed(const Window& w, const PreprocessOptions& o) {
  std::vector<TrajectoryPoint> p = w.points;
  RelativeToFirst(p);
  if (o.transform == "rotate_to_zero") RotateToZero(p);
  return p;
}

// Widens `b` to hold the first `count` points.
void Extend(PositionBounds& b, const std::vector<TrajectoryPoint>& points, size_t count) {
  for (size_t i = 0; i < count && i < points.size(); ++i) {
    b.min_x = std::min(b.min_x, points[i].x), b.max_x = std::max(b.max_x, points[i].x);
    b.min_y = std::min(b.min_y, points[i].y), b.max_y = std::max(b.max_y, points[i].y);
  }
}

constexpr PositionBounds kEmptyBounds{1e300, -1e300, 1e300, -1e300};
}  // namespace

PositionBounds FitPositionBounds(const std::vector<Window>& windows, const PreprocessOptions& o) {
  if (windows.empty()) return {};
  PositionBounds b = kEmptyBounds;
  for (const auto& w : windows) {
    const auto points = Transformed(w, o);
    Extend(b, points, points.size());
  }
  return b;
}

std::vector<float> Features(const Window& w, const PreprocessOptions& o, const MapFeatures& map,
                            const PositionBounds& global) {
  const int n = o.length, valid = std::min(w.valid, n);
  const std::vector<TrajectoryPoint> pos = Transformed(w, o);
  PositionBounds b = global;
  if (o.normalisation == "fixed") {
    // Positions are relative to the first point: ±position_extent maps to [0, 1], so
    // the window's size survives (min-max over the window removes it).
    b = {-o.position_extent, o.position_extent, -o.position_extent, o.position_extent};
  } else if (o.normalisation == "local") {
    b = kEmptyBounds;
    Extend(b, pos, static_cast<size_t>(valid));
  }
  // X' = (X − Xmin) / (Xmax − Xmin); a degenerate range maps to 0.
  auto scale = [](double v, double lo, double hi) { return hi > lo ? Clamp01((v - lo) / (hi - lo)) : 0.0; };
  // Log-scaled features: log(1 + v) / log(1 + cap), for values spread over decades.
  auto log_scale = [](double v, double cap) {
    return cap > 0 ? Clamp01(std::log1p(std::max(0.0, v)) / std::log1p(cap)) : 0.0;
  };
  std::vector<double> dt(valid, 0), speed(valid, 0), course(valid, 0), accel(valid, 0), turn(valid, 0);
  for (int i = 1; i < valid; ++i) {
    const auto &a = w.points[i - 1], &c = w.points[i];
    dt[i] = c.t_s - a.t_s;
    const double dx = c.x - a.x, dy = c.y - a.y, step = std::hypot(dx, dy);
    speed[i] = dt[i] > 0 ? step / dt[i] : speed[i - 1];
    course[i] = step > 1e-9 ? std::atan2(dy, dx) : course[i - 1];
    if (course[i] < 0) course[i] += 2 * M_PI;
  }
  if (valid > 1) speed[0] = speed[1], course[0] = course[1];
  for (int i = 1; i < valid; ++i) {
    if (dt[i] <= 0) continue;
    accel[i] = (speed[i] - speed[i - 1]) / dt[i];
    turn[i] = std::remainder(course[i] - course[i - 1], 2 * M_PI) / dt[i];
  }
  std::vector<float> out(static_cast<size_t>(FeatureRows(o)) * n, 0.0f);
  // One row per feature (the category's several); names resolved once per row.
  float* row = out.data();
  for (const std::string& name : o.features) {
    const bool log = std::find(o.log_scaled.begin(), o.log_scaled.end(), name) != o.log_scaled.end();
    auto fill = [&](auto value_at) {
      for (int i = 0; i < valid; ++i) row[i] = static_cast<float>(value_at(i));
      row += n;
    };
    auto fill_map = [&](const std::function<double(double, double)>& fn, double cap) {
      if (!fn) return fill([](int) { return 0.0; });
      fill([&](int i) {
        const double d = fn(w.points[i].x, w.points[i].y);
        return log ? log_scale(d, cap) : scale(d, 0, cap);
      });
    };
    auto fill_region = [&](int axis) {
      if (!map.region) return fill([](int) { return 0.0; });
      fill([&](int i) { return Clamp01(map.region(w.points[i].x, w.points[i].y)[axis]); });
    };
    auto fill_category = [&] {
      const double u = scale(w.category, 0, o.category_cap);
      fill([&](int) { return u; });
      for (int k = 0; k < o.category_frequencies; ++k) {
        const double phase = 2 * M_PI * std::ldexp(u, k);
        fill([&](int) { return 0.5 + 0.5 * std::sin(phase); });
        fill([&](int) { return 0.5 + 0.5 * std::cos(phase); });
      }
    };
    if (name == "x")
      fill([&](int i) { return scale(pos[i].x, b.min_x, b.max_x); });
    else if (name == "y")
      fill([&](int i) { return scale(pos[i].y, b.min_y, b.max_y); });
    else if (name == "dt")
      fill([&](int i) { return log ? log_scale(dt[i], o.max_gap_s) : scale(dt[i], 0, o.max_gap_s); });
    else if (name == "speed")
      fill([&](int i) { return scale(speed[i], 0, o.max_speed); });
    else if (name == "course")
      fill([&](int i) { return scale(course[i], 0, 2 * M_PI); });
    else if (name == "heading") {
      fill([&](int i) { return 0.5 + 0.5 * std::sin(course[i]); });
      fill([&](int i) { return 0.5 + 0.5 * std::cos(course[i]); });
    } else if (name == "accel")
      fill([&](int i) { return scale(accel[i], -o.max_accel, o.max_accel); });
    else if (name == "turn_rate")
      fill([&](int i) { return scale(turn[i], -o.max_turn_rate, o.max_turn_rate); });
    else if (name == "dist_static")
      fill_map(map.distance_to_static, o.static_cap);
    else if (name == "dist_poi")
      fill_map(map.distance_to_poi, o.poi_cap);
    else if (name == "region_x")
      fill_region(0);
    else if (name == "region_y")
      fill_region(1);
    else if (name == "category")
      fill_category();
  }
  return out;
}

}  // namespace specht::classify
