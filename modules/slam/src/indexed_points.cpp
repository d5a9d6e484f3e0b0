#include "specht/slam/indexed_points.h"

#include <mrpt/poses/CPose2D.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace specht::slam {

namespace {

// Ranges this small are scanned point by point rather than split further.
constexpr size_t kLeafSize = 16;

float Distance2(float qx, float qy, float px, float py) {
  const float dx = qx - px, dy = qy - py;
  return dx * dx + dy * dy;
}

}  // namespace

IndexedPoints::IndexedPoints(const mrpt::maps::CSimplePointsMap& points) : CSimplePointsMap(points) {
  const auto& xs = getPointsBufferRef_x();
  const auto& ys = getPointsBufferRef_y();
  tree_.resize(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) tree_[i] = {xs[i], ys[i], static_cast<uint32_t>(i)};
  axis_.assign(tree_.size(), 0);
  if (tree_.empty()) return;
  Box box{xs[0], xs[0], ys[0], ys[0]};
  for (const TreePoint& p : tree_) {
    box.x0 = std::min(box.x0, p.x), box.x1 = std::max(box.x1, p.x);
    box.y0 = std::min(box.y0, p.y), box.y1 = std::max(box.y1, p.y);
  }
  Build(0, tree_.size(), box);
}

// Split [lo, hi) at its median along the longer side of its box. The box is the
// parent's cut at the split (it bounds the points without a pass over them).
void IndexedPoints::Build(size_t lo, size_t hi, Box box) {
  if (hi - lo <= kLeafSize) return;
  const uint8_t axis = (box.y1 - box.y0) > (box.x1 - box.x0) ? 1 : 0;
  const size_t mid = lo + (hi - lo) / 2;
  auto begin = tree_.begin();
  if (axis == 0) {
    std::nth_element(begin + lo, begin + mid, begin + hi,
                     [](const TreePoint& a, const TreePoint& b) { return a.x < b.x; });
  } else {
    std::nth_element(begin + lo, begin + mid, begin + hi,
                     [](const TreePoint& a, const TreePoint& b) { return a.y < b.y; });
  }
  axis_[mid] = axis;
  Box left = box, right = box;
  if (axis == 0) {
    left.x1 = right.x0 = tree_[mid].x;
  } else {
    left.y1 = right.y0 = tree_[mid].y;
  }
  Build(lo, mid, left);
  Build(mid + 1, hi, right);
}

namespace {

// Offers `visit` every point of [lo, hi) that could lie nearer than its bound2, the
// near half of every split first; the far half only when the split line is nearer
// than the bound (every point there is at least |q − split| away, and float rounding
// is monotonic, so this holds as computed). Tracking the far half's whole box, as
// nanoflann does, prunes a little more but is no faster for the short radius queries of
// scan matching (bench/point_index_bench).
template <class Tree, class Visitor>
void Search(const Tree& tree, const std::vector<uint8_t>& axes, size_t lo, size_t hi, float x, float y,
            Visitor& visit) {
  while (hi - lo > kLeafSize) {
    const size_t mid = lo + (hi - lo) / 2;
    const auto& p = tree[mid];
    visit(p);
    const float diff = axes[mid] == 0 ? x - p.x : y - p.y;
    if (diff < 0) {
      Search(tree, axes, lo, mid, x, y, visit);
      lo = mid + 1;
    } else {
      Search(tree, axes, mid + 1, hi, x, y, visit);
      hi = mid;
    }
    if (!(diff * diff < visit.bound2)) return;
  }
  for (size_t i = lo; i < hi; ++i) visit(tree[i]);
}

}  // namespace

std::optional<IndexedPoints::Neighbour> IndexedPoints::Nearest(float x, float y, float bound2) const {
  struct Best {
    float qx, qy, bound2;
    std::optional<Neighbour> found;
    void operator()(const TreePoint& p) {
      const float d2 = Distance2(qx, qy, p.x, p.y);
      if (d2 < bound2) bound2 = d2, found = Neighbour{p.index, d2};
    }
  } best{x, y, bound2, std::nullopt};
  Search(tree_, axis_, 0, tree_.size(), x, y, best);
  return best.found;
}

void IndexedPoints::Nearest(float x, float y, size_t k, float bound2, std::vector<Neighbour>& out) const {
  out.clear();
  if (k == 0) return;
  // `out` holds the best so far, nearest first; bound2 is what a point must beat to
  // enter it (the k-th's distance once there are k).
  struct KBest {
    float qx, qy, bound2;
    size_t k;
    std::vector<Neighbour>& out;
    void operator()(const TreePoint& p) {
      const float d2 = Distance2(qx, qy, p.x, p.y);
      if (!(d2 < bound2)) return;
      // Insertion into the sorted list, after any of equal distance; a full list drops its last.
      size_t i = out.size() < k ? out.size() : k - 1;
      if (i == out.size()) out.emplace_back();
      for (; i > 0 && out[i - 1].distance2 > d2; --i) out[i] = out[i - 1];
      out[i] = Neighbour{p.index, d2};
      if (out.size() == k) bound2 = out.back().distance2;
    }
  } best{x, y, bound2, k, out};
  Search(tree_, axis_, 0, tree_.size(), x, y, best);
}

void IndexedPoints::Within(float x, float y, float bound2, std::vector<Neighbour>& out) const {
  out.clear();
  struct All {
    float qx, qy;
    const float bound2;
    std::vector<Neighbour>& out;
    void operator()(const TreePoint& p) {
      const float d2 = Distance2(qx, qy, p.x, p.y);
      if (d2 < bound2) out.push_back({p.index, d2});
    }
  } all{x, y, bound2, out};
  Search(tree_, axis_, 0, tree_.size(), x, y, all);
}

// CPointsMap::determineMatching2D with this tree in place of nanoflann's. For every
// `decimation`-th point s_i of the other cloud (from `offset`), moved by the pose
// q_i = t + R(θ) s_i, pair it with its nearest point m here when
//   |q_i − m|² < (max_angular · |q_i − pivot| + max_distance)².
// q_i is computed as MRPT 2.5 computes it, in float from left to right (a test checks
// the squared distances bit for bit against MRPT's).
void IndexedPoints::determineMatching2D(const mrpt::maps::CMetricMap* other_map, const mrpt::poses::CPose2D& other_pose,
                                        mrpt::tfest::TMatchingPairList& pairs,
                                        const mrpt::maps::TMatchingParams& params,
                                        mrpt::maps::TMatchingExtraResults& extra) const {
  if (params.onlyUniqueRobust || !params.onlyKeepTheClosest) {
    CSimplePointsMap::determineMatching2D(other_map, other_pose, pairs, params, extra);  // MRPT's own
    return;
  }
  extra = mrpt::maps::TMatchingExtraResults();
  pairs.clear();
  const auto* other = dynamic_cast<const mrpt::maps::CPointsMap*>(other_map);
  if (other == nullptr) throw std::invalid_argument("IndexedPoints: ICP's other map is not a point cloud");
  if (params.decimation_other_map_points == 0 || params.offset_other_map_points >= params.decimation_other_map_points) {
    throw std::invalid_argument("IndexedPoints: ICP point decimation must be positive and above its offset");
  }
  const size_t n = other->size();
  if (empty() || n == 0) return;

  const float sf = static_cast<float>(std::sin(other_pose.phi())), cf = static_cast<float>(std::cos(other_pose.phi()));
  const float x0 = static_cast<float>(other_pose.x()), y0 = static_cast<float>(other_pose.y());
  const auto& ox = other->getPointsBufferRef_x();
  const auto& oy = other->getPointsBufferRef_y();
  const auto& oz = other->getPointsBufferRef_z();
  const auto& mx = getPointsBufferRef_x();
  const auto& my = getPointsBufferRef_y();
  const auto& mz = getPointsBufferRef_z();
  const auto& pivot = params.angularDistPivotPoint;

  float sum2 = 0;
  size_t paired = 0;
  pairs.reserve(n / params.decimation_other_map_points + 1);
  for (size_t i = params.offset_other_map_points; i < n; i += params.decimation_other_map_points) {
    const float qx = x0 + cf * ox[i] - sf * oy[i], qy = y0 + sf * ox[i] + cf * oy[i];
    const double from_pivot = std::sqrt((pivot.x - qx) * (pivot.x - qx) + (pivot.y - qy) * (pivot.y - qy));
    const double gate = params.maxAngularDistForCorrespondence * from_pivot + params.maxDistForCorrespondence;
    const double gate2 = gate * gate;
    // Every float not above float(gate2) is searched; what lies above it is above gate2.
    const auto nearest = Nearest(qx, qy, std::nextafter(static_cast<float>(gate2), INFINITY));
    if (!nearest || !(nearest->distance2 < gate2)) continue;
    const uint32_t j = nearest->index;
    mrpt::tfest::TMatchingPair& p = pairs.emplace_back();
    p.globalIdx = j;
    p.global = {mx[j], my[j], mz[j]};
    p.localIdx = static_cast<uint32_t>(i);
    p.local = {ox[i], oy[i], oz[i]};
    p.errorSquareAfterTransformation = nearest->distance2;
    sum2 += nearest->distance2;
    ++paired;
  }
  extra.sumSqrDist = paired > 0 ? static_cast<float>(sum2 / static_cast<double>(paired)) : 0.0f;
  extra.correspondencesRatio = static_cast<float>(params.decimation_other_map_points * paired) / static_cast<float>(n);
}

}  // namespace specht::slam
