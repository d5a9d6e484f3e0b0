#include "specht/slam/correlative_matcher.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>

#include <opencv2/imgproc.hpp>

namespace specht::slam {

using mrpt::poses::CPose2D;

CorrelativeMatcher::CorrelativeMatcher(const mrpt::maps::CSimplePointsMap& map_points, double resolution_m,
                                       double max_window_m, double blur_cells)
    : resolution_(resolution_m) {
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

  // L(c) = exp(−d²/2σ²) from the distance transform of the hit mask.
  cv::Mat free(height_, width_, CV_8U, cv::Scalar(255));
  for (size_t i = 0; i < xs.size(); ++i) {
    const int cx = static_cast<int>((xs[i] - x0_) / resolution_m), cy = static_cast<int>((ys[i] - y0_) / resolution_m);
    free.at<uint8_t>(cy, cx) = 0;
  }
  cv::Mat dist;
  cv::distanceTransform(free, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  Level base;
  base.cells.resize(static_cast<size_t>(width_) * height_);
  const double inv_two_sigma2 = 1.0 / (2.0 * blur_cells * blur_cells);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const float d = dist.at<float>(y, x);
      base.cells[static_cast<size_t>(y) * width_ + x] = static_cast<uint8_t>(std::lround(255.0 * std::exp(-d * d * inv_two_sigma2)));
    }
  }
  levels_.push_back(std::move(base));

  // P_h(c) = max(P_{h−1}(c), P_{h−1}(c + (s, 0)), P_{h−1}(c + (0, s)), P_{h−1}(c + (s, s))), s = 2^{h−1}.
  const int window_cells = static_cast<int>(std::ceil(max_window_m / resolution_m));
  for (int h = 1; (1 << (h - 1)) < std::max(1, window_cells); ++h) {
    const int s = 1 << (h - 1);
    Level next;
    next.cells.resize(levels_.back().cells.size());
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        next.cells[static_cast<size_t>(y) * width_ + x] =
            std::max({At(h - 1, x, y), At(h - 1, x + s, y), At(h - 1, x, y + s), At(h - 1, x + s, y + s)});
      }
    }
    levels_.push_back(std::move(next));
  }
}

uint8_t CorrelativeMatcher::At(int level, int cx, int cy) const {
  if (cx < 0 || cy < 0 || cx >= width_ || cy >= height_) return 0;
  return levels_[level].cells[static_cast<size_t>(cy) * width_ + cx];
}

size_t CorrelativeMatcher::MemoryBytes() const { return levels_.size() * static_cast<size_t>(width_) * height_; }

double CorrelativeMatcher::Score(const mrpt::maps::CSimplePointsMap& scan, const CPose2D& pose) const {
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
  return sum / (255.0 * xs.size());
}

namespace {

struct Candidate {
  int angle = 0;  // index into the rotated scans
  int dx = 0, dy = 0;
  int score = 0;  // sum of cell values over the points
  bool operator<(const Candidate& o) const { return score > o.score; }  // best first
};

}  // namespace

std::optional<CorrelativeResult> CorrelativeMatcher::Match(const mrpt::maps::CSimplePointsMap& scan,
                                                           const CPose2D& guess, double window_m, double window_rad,
                                                           double min_score) const {
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

  // Cells of the scan rotated by each angle and placed at the guess position.
  std::vector<std::vector<std::pair<int, int>>> cells(2 * half_angles + 1);
  for (int a = -half_angles; a <= half_angles; ++a) {
    const double th = guess.phi() + a * step, c = std::cos(th), s = std::sin(th);
    auto& v = cells[a + half_angles];
    v.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      const double x = guess.x() + c * xs[i] - s * ys[i], y = guess.y() + s * xs[i] + c * ys[i];
      v.emplace_back(static_cast<int>(std::floor((x - x0_) / resolution_)),
                     static_cast<int>(std::floor((y - y0_) / resolution_)));
    }
  }
  auto bound = [&](int level, const Candidate& c) {
    int sum = 0;
    for (const auto& [cx, cy] : cells[c.angle]) sum += At(level, cx + c.dx, cy + c.dy);
    return sum;
  };

  // Top level: translations on a lattice of 2^top cells.
  std::vector<Candidate> roots;
  for (size_t a = 0; a < cells.size(); ++a) {
    for (int dx = -w; dx <= w; dx += 1 << top) {
      for (int dy = -w; dy <= w; dy += 1 << top) {
        Candidate c{static_cast<int>(a), dx, dy, 0};
        c.score = bound(top, c);
        roots.push_back(c);
      }
    }
  }
  std::sort(roots.begin(), roots.end());
  const int min_sum = static_cast<int>(std::ceil(min_score * 255.0 * n));
  Candidate best{0, 0, 0, min_sum - 1};
  bool found = false;

  // Depth-first, best child first; cut branches whose bound cannot beat `best`.
  std::function<void(const Candidate&, int)> search = [&](const Candidate& c, int level) {
    if (c.score <= best.score) return;
    if (level == 0) {
      best = c;
      found = true;
      return;
    }
    const int s = 1 << (level - 1);
    std::vector<Candidate> children;
    for (int ox : {0, s}) {
      for (int oy : {0, s}) {
        Candidate child{c.angle, c.dx + ox, c.dy + oy, 0};
        if (child.dx > w || child.dy > w) continue;
        child.score = bound(level - 1, child);
        children.push_back(child);
      }
    }
    std::sort(children.begin(), children.end());
    for (const auto& child : children) search(child, level - 1);
  };
  for (const auto& root : roots) {
    if (root.score <= best.score) break;
    search(root, top);
  }
  if (!found) return std::nullopt;
  const double th = guess.phi() + (best.angle - half_angles) * step;
  return CorrelativeResult{CPose2D(guess.x() + best.dx * resolution_, guess.y() + best.dy * resolution_, th),
                           best.score / (255.0 * n)};
}

mrpt::maps::CSimplePointsMap Decimate(const mrpt::maps::CSimplePointsMap& points, double cell_m) {
  mrpt::maps::CSimplePointsMap out;
  std::set<std::pair<long, long>> seen;
  const auto& xs = points.getPointsBufferRef_x();
  const auto& ys = points.getPointsBufferRef_y();
  for (size_t i = 0; i < xs.size(); ++i) {
    const std::pair<long, long> key(std::lround(std::floor(xs[i] / cell_m)), std::lround(std::floor(ys[i] / cell_m)));
    if (seen.insert(key).second) out.insertPoint(xs[i], ys[i], 0);
  }
  return out;
}

}  // namespace specht::slam
