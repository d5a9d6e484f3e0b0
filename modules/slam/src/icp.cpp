#include "specht/slam/icp.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/slam/CICP.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace specht::slam {

struct IcpAligner::Impl {
  mrpt::slam::CICP icp;
  IcpOptions options;
  std::vector<IndexedPoints::Neighbour> neighbours;  // scratch for the k-d tree queries
};

namespace {

// Fewer pairs than this leave the refinement where ICP put the scan.
constexpr int kMinLinePairs = 10;
// Neighbours whose spread across their line exceeds this fraction of the spread along
// it are a corner or clutter, not a line.
constexpr double kMaxLineFlatness = 0.1;
// Neighbours spread along their line by less than this (Σ of squared offsets, m²: five
// points 0.3 mm apart) sit on one spot, whatever direction rounding gives them.
constexpr double kMinLineSpread = 1e-6;
// ICP's pose and the guess closer than this in heading (and half the gate apart) refine
// to the same pose: the guess is not refined separately.
constexpr double kSameBasinRad = M_PI / 180;

// The line through the map points nearest to (qx, qy): their mean and normal, when the
// nearest lies within the gate, all within twice the gate, and they lie on a line.
struct Line {
  double mx = 0, my = 0;
  Eigen::Vector2d normal;
};
std::optional<Line> LineNear(const IndexedPoints& reference, double qx, double qy, const IcpOptions& o,
                             std::vector<IndexedPoints::Neighbour>& near) {
  const size_t k = static_cast<size_t>(o.point_to_line_neighbours);
  const double gate2 = o.point_to_line_gate_m * o.point_to_line_gate_m;
  // Every float not above float(4 gate²) is searched; what lies above it is above 4 gate².
  const float bound2 = std::nextafter(static_cast<float>(4 * gate2), INFINITY);
  reference.Nearest(static_cast<float>(qx), static_cast<float>(qy), k, bound2, near);
  if (near.size() < k || near[0].distance2 > gate2 || near[k - 1].distance2 > 4 * gate2) return std::nullopt;
  const auto& rx = reference.points().getPointsBufferRef_x();
  const auto& ry = reference.points().getPointsBufferRef_y();
  Line line;
  for (const auto& n : near) line.mx += rx[n.index], line.my += ry[n.index];
  line.mx /= k, line.my /= k;
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  for (const auto& n : near) {
    const Eigen::Vector2d v(rx[n.index] - line.mx, ry[n.index] - line.my);
    spread += v * v.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(spread);
  // (Neighbours on one spot, a point seen again from the same pose, have no line.)
  if (!(eig.eigenvalues()(1) > kMinLineSpread) || eig.eigenvalues()(0) > kMaxLineFlatness * eig.eigenvalues()(1))
    return std::nullopt;
  line.normal = eig.eigenvectors().col(0);
  return line;
}

// A refined pose and how well the scan lies on the map's lines there: the truncated
// cost Σ min(r_i², gate²) over every scan point, r_i its distance to the line near it
// (a point with no line near costs the full gate²). Lower is better; comparable
// between poses of the same scan.
struct LineFit {
  mrpt::poses::CPose2D pose;
  double cost = 0;
  int pairs = 0;             // scan points with a line near them
  std::vector<bool> paired;  // which (the last pass)
};

// The point-to-line refinement of `pose` (see icp.h): Gauss–Newton on the Huber-weighted
// normal equations H δ = −g, H = Σ w J Jᵀ, g = Σ w J r. With `score`, one more pass
// computes the cost at the pose returned (only needed to compare two refinements);
// without it the cost is that of the pose before the last step.
LineFit RefinePointToLine(const IndexedPoints& reference, const mrpt::maps::CSimplePointsMap& scan,
                          mrpt::poses::CPose2D pose, const IcpOptions& o, bool score, const IcpPrior* prior,
                          std::vector<IndexedPoints::Neighbour>& near) {
  LineFit fit;
  const int passes = o.point_to_line_iterations + (score ? 1 : 0);
  const auto& xs = scan.getPointsBufferRef_x();
  const auto& ys = scan.getPointsBufferRef_y();
  const double gate2 = o.point_to_line_gate_m * o.point_to_line_gate_m, huber = 0.5 * o.point_to_line_gate_m;
  for (int it = 0; it < passes; ++it) {
    const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    fit = LineFit{pose, 0, 0, std::vector<bool>(xs.size(), false)};
    for (size_t i = 0; i < xs.size(); ++i) {
      const double qx = pose.x() + c * xs[i] - s * ys[i], qy = pose.y() + s * xs[i] + c * ys[i];
      const auto line = LineNear(reference, qx, qy, o, near);
      if (!line) {
        fit.cost += gate2;
        continue;
      }
      const Eigen::Vector2d& n = line->normal;
      const double r = n.x() * (qx - line->mx) + n.y() * (qy - line->my);
      fit.cost += std::min(r * r, gate2);
      const double dx = -s * xs[i] - c * ys[i], dy = c * xs[i] - s * ys[i];
      const Eigen::Vector3d j(n.x(), n.y(), n.x() * dx + n.y() * dy);
      const double w = std::abs(r) <= huber ? 1.0 : huber / std::abs(r);
      h += w * j * j.transpose();
      g += w * r * j;
      ++fit.pairs;
      fit.paired[i] = true;
    }
    if (prior) {
      const Eigen::Matrix3d w = prior->point_sigma_m * prior->point_sigma_m * prior->information;
      const Eigen::Vector3d e(pose.x() - prior->pose.x(), pose.y() - prior->pose.y(),
                              mrpt::math::wrapToPi(pose.phi() - prior->pose.phi()));
      h += w;
      g += w * e;
      fit.cost += e.dot(w * e);
    }
    // With `score`, the last pass only scores the pose the steps before it reached.
    if (it == o.point_to_line_iterations || fit.pairs < kMinLinePairs) break;
    const Eigen::Vector3d step = -h.ldlt().solve(g);
    if (!step.allFinite()) break;
    pose = mrpt::poses::CPose2D(pose.x() + step.x(), pose.y() + step.y(), mrpt::math::wrapToPi(pose.phi() + step.z()));
    if (step.head<2>().norm() < 1e-4 && std::abs(step.z()) < 1e-5) {  // 0.1 mm, 0.0006°
      if (!score) break;
      it = o.point_to_line_iterations - 1;  // score the converged pose, then stop
    }
  }
  fit.pose = pose;  // without `score`, the last step's pose (fit.cost is from before it)
  return fit;
}

// The scan's own surface normals, in its frame: at each point, the normal of the chord
// between the nearest beams on either side at least kChordM apart, when the beams
// between step less than kSameSurfaceM and the point lies within kCornerM of the
// chord (not a corner). A chord of 0.2 m tilts with 1 cm of range noise by about 4°,
// so a straight wall's normals stay near one direction.
constexpr double kChordM = 0.2, kSameSurfaceM = 0.3, kCornerM = 0.03;
constexpr int kMaxChordHalfBeams = 20;
// Only points with `use` (all when empty).
std::vector<Eigen::Vector2d> ScanNormals(const mrpt::maps::CSimplePointsMap& scan, const std::vector<bool>& use) {
  const auto& xs = scan.getPointsBufferRef_x();
  const auto& ys = scan.getPointsBufferRef_y();
  const int n = static_cast<int>(xs.size());
  auto p = [&](int i) { return Eigen::Vector2d(xs[i], ys[i]); };
  std::vector<Eigen::Vector2d> normals;
  for (int i = 0; i < n; ++i) {
    if (!use.empty() && !use[i]) continue;
    int a = i, b = i;
    while ((p(b) - p(a)).norm() < kChordM && b - a < 2 * kMaxChordHalfBeams) {
      const bool left = a > 0 && (p(a - 1) - p(a)).norm() < kSameSurfaceM;
      const bool right = b + 1 < n && (p(b + 1) - p(b)).norm() < kSameSurfaceM;
      if (!left && !right) break;
      if (left) --a;
      if (right) ++b;
    }
    const Eigen::Vector2d chord = p(b) - p(a);
    if (chord.norm() < kChordM) continue;
    const Eigen::Vector2d normal(-chord.y() / chord.norm(), chord.x() / chord.norm());
    if (std::abs(normal.dot(p(i) - p(a))) > kCornerM) continue;
    normals.push_back(normal);
  }
  return normals;
}

}  // namespace

IcpAligner::IcpAligner(const IcpOptions& options) : impl_(std::make_unique<Impl>()) {
  impl_->options = options;
  auto& o = impl_->icp.options;
  o.ICP_algorithm = mrpt::slam::icpClassic;
  o.maxIterations = options.max_iterations;
  o.thresholdDist = options.max_pair_distance_m;
  o.thresholdAng = mrpt::DEG2RAD(options.max_pair_angle_deg);
  o.ALFA = options.threshold_decay;
  o.smallestThresholdDist = options.min_pair_distance_m;
  o.corresponding_points_decimation = options.point_decimation;
  o.onlyUniqueRobust = false;
  o.skip_cov_calculation = true;
  o.skip_quality_calculation = true;
}

IcpAligner::~IcpAligner() = default;

IcpResult IcpAligner::Align(const IndexedPoints& reference, const mrpt::maps::CSimplePointsMap& scan,
                            const mrpt::poses::CPose2D& guess, const IcpPrior* prior, const IndexedPoints* lines) {
  mrpt::slam::CICP::TReturnInfo info;
  const auto pdf = impl_->icp.Align(&reference.AsIcpReference(), &scan, guess, info);
  mrpt::poses::CPose2D pose = pdf->getMeanVal();
  std::vector<bool> paired;
  const auto& o = impl_->options;
  const IndexedPoints& fitted = lines ? *lines : reference;
  if (o.point_to_line_iterations > 0 && fitted.size() >= static_cast<size_t>(o.point_to_line_neighbours)) {
    // Refine from ICP's pose and, unless ICP ended so near the guess that both would
    // settle in one basin, from the guess too; the lower cost wins, the guess on a tie.
    const mrpt::poses::CPose2D moved = pose - guess;
    const bool two_starts = moved.norm() > 0.5 * o.point_to_line_gate_m || std::abs(moved.phi()) > kSameBasinRad;
    LineFit fit = RefinePointToLine(fitted, scan, pose, o, two_starts, prior, impl_->neighbours);
    if (two_starts) {
      LineFit from_guess = RefinePointToLine(fitted, scan, guess, o, true, prior, impl_->neighbours);
      if (!(fit.cost < from_guess.cost)) fit = std::move(from_guess);
    }
    pose = fit.pose;
    paired = std::move(fit.paired);
  }
  return IcpResult{pose, info.goodness, static_cast<int>(info.nIterations), std::move(paired)};
}

// v is the eigenvector of the smallest eigenvalue of Σ n_i n_iᵀ, turned into the
// reference frame; a point pins it when |n_i·v| ≥ ½.
WeakestAxis WeakestAxisOf(const mrpt::maps::CSimplePointsMap& scan, const IcpResult& result) {
  const std::vector<Eigen::Vector2d> normals = ScanNormals(scan, result.line_paired);
  Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
  for (const auto& n : normals) sum += n * n.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> axes(sum);  // eigenvalues ascending
  const Eigen::Vector2d v = axes.eigenvectors().col(0);
  WeakestAxis out;
  for (const auto& n : normals) out.points += std::abs(n.dot(v)) >= 0.5;
  out.axis = Eigen::Rotation2Dd(result.pose.phi()) * v;
  return out;
}

mrpt::maps::CSimplePointsMap ScanToPoints(const mrpt::obs::CObservation2DRangeScan& scan) {
  mrpt::maps::CSimplePointsMap points;
  points.insertionOptions.minDistBetweenLaserPoints = 0;
  points.insertionOptions.isPlanarMap = true;
  points.insertObservation(scan);
  return points;
}

mrpt::maps::CSimplePointsMap WithinRange(const mrpt::maps::CSimplePointsMap& points, double max_range_m) {
  mrpt::maps::CSimplePointsMap out;
  const auto& xs = points.getPointsBufferRef_x();
  const auto& ys = points.getPointsBufferRef_y();
  for (size_t i = 0; i < xs.size(); ++i) {
    if (std::hypot(xs[i], ys[i]) <= max_range_m) out.insertPoint(xs[i], ys[i], 0);
  }
  return out;
}

}  // namespace specht::slam
