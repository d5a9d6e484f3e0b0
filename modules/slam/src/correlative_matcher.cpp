#include "specht/slam/correlative_matcher.h"

#include <mrpt/math/wrap2pi.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace specht::slam {

using mrpt::poses::CPose2D;

namespace {

// The least of max(0, |v| − slack) and of max(0, −v − slack) over v in [lo, hi].
double SidewaysExcess(double lo, double hi, double slack) {
  if (lo > slack) return lo - slack;
  if (hi < -slack) return -hi - slack;
  return 0;
}
double BackwardExcess(double hi, double slack) { return std::max(0.0, -hi - slack); }

}  // namespace

double DrivePrior::ExcessM(double x, double y, double phi) const { return MinExcessM(x, x, y, y, phi); }

DrivePrior::Axes DrivePrior::AxesAt(double phi) const {
  const double mean_heading = from.phi() + mrpt::math::wrapToPi(phi - from.phi()) / 2;
  return {std::cos(mean_heading), std::sin(mean_heading)};
}

double DrivePrior::MinExcessM(double x0, double x1, double y0, double y1, double phi) const {
  return MinExcessM(x0, x1, y0, y1, AxesAt(phi));
}

double DrivePrior::MinExcessM(double x0, double x1, double y0, double y1, const Axes& axes) const {
  const double c = axes.c, s = axes.s;
  // f and ℓ are linear in (x, y): their extremes over the box are at its corners.
  double f_hi = -std::numeric_limits<double>::infinity();
  double l_lo = std::numeric_limits<double>::infinity(), l_hi = -l_lo;
  for (const double x : {x0, x1}) {
    for (const double y : {y0, y1}) {
      const double dx = x - from.x(), dy = y - from.y();
      f_hi = std::max(f_hi, c * dx + s * dy);
      const double l = -s * dx + c * dy;
      l_lo = std::min(l_lo, l), l_hi = std::max(l_hi, l);
    }
  }
  return SidewaysExcess(l_lo, l_hi, slack_m) + (reverse ? 0.0 : BackwardExcess(f_hi, slack_m));
}

CorrelativeMatcher::CorrelativeMatcher(const mrpt::maps::CSimplePointsMap& map_points, double resolution_m,
                                       double max_window_m, double blur_cells)
    : resolution_(resolution_m) {
  if (!(resolution_m > 0) || !(blur_cells > 0) || !(max_window_m >= 0))
    throw std::invalid_argument("CorrelativeMatcher: resolution and blur must be positive, the window not negative");
  const auto& xs = map_points.getPointsBufferRef_x();
  const auto& ys = map_points.getPointsBufferRef_y();
  double min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  if (!xs.empty()) {
    min_x = *std::min_element(xs.begin(), xs.end()), max_x = *std::max_element(xs.begin(), xs.end());
    min_y = *std::min_element(ys.begin(), ys.end()), max_y = *std::max_element(ys.begin(), ys.end());
  }
  const double pad = max_window_m + 4 * blur_cells * resolution_m + resolution_m;
  x0_ = min_x - pad, y0_ = min_y - pad;
  width_ = static_cast<int>(std::ceil((max_x - min_x + 2 * pad) / resolution_m)) + 1;
  height_ = static_cast<int>(std::ceil((max_y - min_y + 2 * pad) / resolution_m)) + 1;

  // L(c) = exp(−d²/2σ²), d the distance from c to the nearest hit cell: the maximum,
  // over hit cells, of a kernel holding exp(−d²/2σ²) at each offset. 255·exp(−d²/2σ²)
  // rounds to 0 from d²/2σ² > ln 510, so the kernel ends there and most cells stay 0
  // (a distance transform of the whole grid would visit them all).
  const double inv_two_sigma2 = 1.0 / (2.0 * blur_cells * blur_cells);
  const double zero_from_d2 = std::log(510.0) / inv_two_sigma2;
  const int reach = static_cast<int>(std::floor(std::sqrt(zero_from_d2)));
  struct Tap {
    int dx, dy;
    uint8_t value;
  };
  std::vector<Tap> kernel;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const double d2 = dx * dx + dy * dy;
      if (d2 > zero_from_d2) continue;
      const auto value = static_cast<uint8_t>(std::lround(255.0 * std::exp(-d2 * inv_two_sigma2)));
      if (value > 0) kernel.push_back({dx, dy, value});
    }
  }
  Level base;
  base.cells.assign(static_cast<size_t>(width_) * height_, 0);
  std::vector<uint8_t> hit(base.cells.size(), 0);
  for (size_t i = 0; i < xs.size(); ++i) {
    const int cx = static_cast<int>((xs[i] - x0_) / resolution_m), cy = static_cast<int>((ys[i] - y0_) / resolution_m);
    uint8_t& seen = hit[static_cast<size_t>(cy) * width_ + cx];
    if (seen) continue;
    seen = 1;
    // The padding keeps every tap inside the grid.
    for (const Tap& t : kernel) {
      uint8_t& cell = base.cells[static_cast<size_t>(cy + t.dy) * width_ + cx + t.dx];
      cell = std::max(cell, t.value);
    }
  }
  levels_.push_back(std::move(base));

  // P_h(c) = max(P_{h−1}(c), P_{h−1}(c + (s, 0)), P_{h−1}(c + (0, s)), P_{h−1}(c + (s, s))), s = 2^{h−1}.
  const int window_cells = static_cast<int>(std::ceil(max_window_m / resolution_m));
  // As whole-image maxima of shifted copies (cells past the edge count 0, which no
  // maximum of non-negative values notices).
  for (int h = 1; (1 << (h - 1)) < std::max(1, window_cells); ++h) {
    const int s = 1 << (h - 1);
    Level next;
    next.cells = levels_.back().cells;
    cv::Mat prev(height_, width_, CV_8U, levels_.back().cells.data());
    cv::Mat out(height_, width_, CV_8U, next.cells.data());
    for (const auto& [dx, dy] : {std::pair{s, 0}, std::pair{0, s}, std::pair{s, s}}) {
      if (dx >= width_ || dy >= height_) continue;
      const cv::Rect target(0, 0, width_ - dx, height_ - dy), source(dx, dy, width_ - dx, height_ - dy);
      cv::Mat region = out(target);
      cv::max(region, prev(source), region);
    }
    levels_.push_back(std::move(next));
  }
}

uint8_t CorrelativeMatcher::At(int level, int cx, int cy) const {
  if (cx < 0 || cy < 0 || cx >= width_ || cy >= height_) return 0;
  return levels_[level].cells[static_cast<size_t>(cy) * width_ + cx];
}

size_t CorrelativeMatcher::MemoryBytes() const { return levels_.size() * static_cast<size_t>(width_) * height_; }

double CorrelativeMatcher::Score(const mrpt::maps::CSimplePointsMap& scan, const CPose2D& pose,
                                 const DrivePrior& prior) const {
  const auto& xs = scan.getPointsBufferRef_x();
  const auto& ys = scan.getPointsBufferRef_y();
  if (xs.empty()) return 0;
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  long sum = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    const double x = pose.x() + c * xs[i] - s * ys[i], y = pose.y() + s * xs[i] + c * ys[i];
    sum += At(0, static_cast<int>(std::floor((x - x0_) / resolution_)),
              static_cast<int>(std::floor((y - y0_) / resolution_)));
  }
  const double penalty =
      prior.weight_per_m > 0 ? prior.weight_per_m * prior.ExcessM(pose.x(), pose.y(), pose.phi()) : 0;
  return sum / (255.0 * xs.size()) - penalty;
}

namespace {

struct Candidate {
  int angle = 0;  // index into the rotated scans
  int dx = 0, dy = 0;
  int score = 0;                                                        // sum of cell values over the points
  bool operator<(const Candidate& o) const { return score > o.score; }  // best first
};

}  // namespace

std::optional<CorrelativeResult> CorrelativeMatcher::Match(const mrpt::maps::CSimplePointsMap& scan,
                                                           const CPose2D& guess, double window_m, double window_rad,
                                                           double min_score, const DrivePrior& prior) const {
  const auto& xs = scan.getPointsBufferRef_x();
  const auto& ys = scan.getPointsBufferRef_y();
  const size_t n = xs.size();
  if (n == 0) return std::nullopt;
  double max_range = 0;
  for (size_t i = 0; i < n; ++i) max_range = std::max<double>(max_range, std::hypot(xs[i], ys[i]));
  const double step = max_range > resolution_
                          ? std::acos(1.0 - resolution_ * resolution_ / (2.0 * max_range * max_range))
                          : window_rad + 1.0;
  const int half_angles = static_cast<int>(std::ceil(window_rad / step));
  const int w = static_cast<int>(std::ceil(window_m / resolution_));
  const int top = std::min(static_cast<int>(levels_.size()) - 1,
                           std::max(0, static_cast<int>(std::ceil(std::log2(std::max(1, 2 * w + 1)))) - 1));

  // Cells of the scan rotated by each angle and placed at the guess position, with
  // their row-major indices and bounding box (a candidate whose box stays inside the
  // grid sums without a bounds check per point).
  struct Rotated {
    std::vector<std::pair<int, int>> cells;
    std::vector<int> index;
    int min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  };
  std::vector<Rotated> rotated(2 * half_angles + 1);
  for (int a = -half_angles; a <= half_angles; ++a) {
    const double th = guess.phi() + a * step, c = std::cos(th), s = std::sin(th);
    Rotated& r = rotated[a + half_angles];
    r.cells.reserve(n);
    r.index.reserve(n);
    r.min_x = r.min_y = std::numeric_limits<int>::max();
    r.max_x = r.max_y = std::numeric_limits<int>::min();
    for (size_t i = 0; i < n; ++i) {
      const double x = guess.x() + c * xs[i] - s * ys[i], y = guess.y() + s * xs[i] + c * ys[i];
      const int cx = static_cast<int>(std::floor((x - x0_) / resolution_));
      const int cy = static_cast<int>(std::floor((y - y0_) / resolution_));
      r.cells.emplace_back(cx, cy);
      r.index.push_back(cy * width_ + cx);
      r.min_x = std::min(r.min_x, cx), r.max_x = std::max(r.max_x, cx);
      r.min_y = std::min(r.min_y, cy), r.max_y = std::max(r.max_y, cy);
    }
  }
  // Sum of level values over the candidate's cells. `beat` > 0: stop once the rest,
  // at most 255 a point, can no longer lift the sum above `beat` (the caller cuts it).
  auto bound = [&](int level, const Candidate& c, int beat = 0) {
    const uint8_t* cells_at = levels_[level].cells.data();
    const Rotated& r = rotated[c.angle];
    const int count = static_cast<int>(r.index.size());
    // sum + 255·(points left) ≤ beat  ⇔  sum − 255·(points done) ≤ beat − 255·count
    const int give_up = beat > 0 ? beat - 255 * count : std::numeric_limits<int>::min();
    int sum = 0;
    if (r.min_x + c.dx >= 0 && r.min_y + c.dy >= 0 && r.max_x + c.dx < width_ && r.max_y + c.dy < height_) {
      const int offset = c.dy * width_ + c.dx;
      for (int i = 0; i < count; ++i) {
        sum += cells_at[r.index[i] + offset];
        if (sum - 255 * (i + 1) <= give_up) return sum;
      }
      return sum;
    }
    // A cell left of or below the grid at a coarse level still stands for a block
    // (cx .. cx + 2^level − 1) that may reach into it: P at the grid's edge cell
    // bounds that part, so the bound stays admissible.
    const int span = (1 << level) - 1;
    for (int i = 0; i < count; ++i) {
      int cx = r.cells[i].first + c.dx, cy = r.cells[i].second + c.dy;
      if (cx < 0 && cx + span >= 0) cx = 0;
      if (cy < 0 && cy + span >= 0) cy = 0;
      if (cx >= 0 && cy >= 0 && cx < width_ && cy < height_) sum += cells_at[static_cast<size_t>(cy) * width_ + cx];
      if (sum - 255 * (i + 1) <= give_up) return sum;
    }
    return sum;
  };
  // The prior's least penalty over the translations a candidate at `level` stands for
  // (dx .. dx + 2^level − 1, the same in y), in the sums' units, rounded down so that
  // no leaf below loses less.
  const double penalty_units_per_m = prior.weight_per_m * 255.0 * n;
  std::vector<DrivePrior::Axes> axes;
  if (penalty_units_per_m > 0) {
    for (int a = -half_angles; a <= half_angles; ++a) axes.push_back(prior.AxesAt(guess.phi() + a * step));
  }
  auto penalty = [&](int level, const Candidate& c) {
    if (penalty_units_per_m <= 0) return 0;
    const double span = ((1 << level) - 1) * resolution_;
    const double x0 = guess.x() + c.dx * resolution_, y0 = guess.y() + c.dy * resolution_;
    return static_cast<int>(
        std::floor(penalty_units_per_m * prior.MinExcessM(x0, x0 + span, y0, y0 + span, axes[c.angle])));
  };
  // The bound less the penalty. A sum must now beat `beat` + penalty to matter.
  auto scored = [&](int level, const Candidate& c, int beat = 0) {
    const int p = penalty(level, c);
    return bound(level, c, beat > 0 ? beat + p : beat) - p;
  };

  // Top level: translations on a lattice of 2^top cells.
  const int min_sum = static_cast<int>(std::ceil(min_score * 255.0 * n));
  std::vector<Candidate> roots;
  for (size_t a = 0; a < rotated.size(); ++a) {
    for (int dx = -w; dx <= w; dx += 1 << top) {
      for (int dy = -w; dy <= w; dy += 1 << top) {
        Candidate c{static_cast<int>(a), dx, dy, 0};
        c.score = scored(top, c, min_sum - 1);
        roots.push_back(c);
      }
    }
  }
  std::sort(roots.begin(), roots.end());
  Candidate best{0, 0, 0, min_sum - 1};
  bool found = false;

  // Depth-first, best child first; cut branches whose bound cannot beat `best`.
  auto search = [&](auto& self, const Candidate& c, int level) -> void {
    if (c.score <= best.score) return;
    if (level == 0) {
      best = c;
      found = true;
      return;
    }
    const int s = 1 << (level - 1);
    std::array<Candidate, 4> children;
    size_t count = 0;
    for (int ox : {0, s}) {
      for (int oy : {0, s}) {
        Candidate child{c.angle, c.dx + ox, c.dy + oy, 0};
        if (child.dx > w || child.dy > w) continue;
        child.score = scored(level - 1, child, best.score);
        children[count++] = child;
      }
    }
    for (size_t i = 1; i < count; ++i) {  // best first (insertion sort of at most four)
      for (size_t j = i; j > 0 && children[j] < children[j - 1]; --j) std::swap(children[j], children[j - 1]);
    }
    for (size_t i = 0; i < count; ++i) self(self, children[i], level - 1);
  };
  for (const auto& root : roots) {
    if (root.score <= best.score) break;
    search(search, root, top);
  }
  if (!found) return std::nullopt;
  const double th = guess.phi() + (best.angle - half_angles) * step;
  return CorrelativeResult{CPose2D(guess.x() + best.dx * resolution_, guess.y() + best.dy * resolution_, th),
                           best.score / (255.0 * n)};
}

namespace {
uint64_t CellKey(float x, float y, double cell_m) {
  const auto cx = static_cast<int32_t>(std::floor(x / cell_m)), cy = static_cast<int32_t>(std::floor(y / cell_m));
  return (static_cast<uint64_t>(static_cast<uint32_t>(cx)) << 32) | static_cast<uint32_t>(cy);
}
}  // namespace

mrpt::maps::CSimplePointsMap Decimate(const mrpt::maps::CSimplePointsMap& points, double cell_m) {
  mrpt::maps::CSimplePointsMap out;
  const auto& xs = points.getPointsBufferRef_x();
  const auto& ys = points.getPointsBufferRef_y();
  std::unordered_set<uint64_t> seen;
  seen.reserve(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) {
    if (seen.insert(CellKey(xs[i], ys[i], cell_m)).second) out.insertPoint(xs[i], ys[i], 0);
  }
  return out;
}

mrpt::maps::CSimplePointsMap CellMeans(const mrpt::maps::CSimplePointsMap& points, double cell_m) {
  const auto& xs = points.getPointsBufferRef_x();
  const auto& ys = points.getPointsBufferRef_y();
  std::unordered_map<uint64_t, size_t> index;  // cell → its slot, in the order cells were first met
  index.reserve(xs.size());
  std::vector<Eigen::Vector3d> sums;  // x, y, count
  for (size_t i = 0; i < xs.size(); ++i) {
    const auto [it, fresh] = index.try_emplace(CellKey(xs[i], ys[i], cell_m), sums.size());
    if (fresh) sums.emplace_back(0, 0, 0);
    sums[it->second] += Eigen::Vector3d(xs[i], ys[i], 1);
  }
  mrpt::maps::CSimplePointsMap out;
  out.reserve(sums.size());
  for (const auto& s : sums) out.insertPoint(static_cast<float>(s.x() / s.z()), static_cast<float>(s.y() / s.z()), 0);
  return out;
}

}  // namespace specht::slam
