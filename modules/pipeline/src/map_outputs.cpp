#include "internal/map_outputs.h"

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPoint2D.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/core.hpp>

#include "specht/core/error.h"
#include "specht/core/log.h"
#include "specht/eval/map_agreement.h"
#include "specht/eval/map_quality.h"
#include "specht/eval/relation_error.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/dataset.h"
#include "specht/io/map_io.h"
#include "specht/slam/localizer.h"

namespace specht::pipeline::internal {

// Metrics against the reference, when there is one; returns the reference moved into
// the map frame for the picture.
Trajectory AddReferenceMetrics(const Trajectory& trajectory, const Trajectory& reference, nlohmann::json& metrics) {
  if (reference.empty() || trajectory.size() < 2) return {};
  try {
    const auto ate = eval::AbsoluteTrajectoryError2D(trajectory, reference, 0.05);
    metrics["ate"] = eval::ToJson(ate);
    eval::RelationOptions rel_options;
    rel_options.max_dt_s = 0.05;
    const auto rel = eval::ComputeRelationError(trajectory, reference, rel_options);
    metrics["relation"] = eval::ToJson(rel);
    spdlog::info(
        "against the reference: ATE RMSE {:.3f} m; relation error {:.4f} ± {:.4f} m (max {:.3f}), "
        "{:.3f} ± {:.3f} deg over {} relations",
        ate.rmse_m, rel.all.mean_m, rel.all.std_m, rel.all.max_m, rel.all.mean_deg, rel.all.std_deg, rel.all.count);
    return eval::Transform(reference, -ate.alignment);
  } catch (const InputError& e) {
    spdlog::warn("reference not used: {}", e.what());
    return {};
  }
}

std::vector<io::PathOverlay> RelationOverlays(const Trajectory& estimate, const Trajectory& worst, size_t count) {
  return {{&estimate, {30, 90, 220}, "estimate"},
          {&worst, {220, 30, 30}, "the " + std::to_string(count) + " worst relations", false, true}};
}

void AddPublishedRelationMetrics(const Trajectory& trajectory, const io::RelationsFile& relations,
                                 const mrpt::maps::COccupancyGridMap2D& grid, const std::string& out,
                                 nlohmann::json& metrics) {
  auto& m = metrics["published_relations"];
  m["file"] = relations.path;
  try {
    const auto rel = eval::ComputePublishedRelationError(trajectory, relations);
    m.update(eval::ToJson(rel));
    const auto& a = rel.absolute;
    spdlog::info("published relations ({}): {:.4f} ± {:.4f} m (max {:.3f}), {:.3f} ± {:.3f} deg (max {:.2f})",
                 rel.relations, a.mean_m, a.std_m, a.max_m, a.mean_deg, a.std_deg, a.max_deg);
    const Trajectory worst = eval::RelationSegments(trajectory, rel.worst);
    io::WriteMapPng(grid, RelationOverlays(trajectory, worst, rel.worst.size()), out + "/relations.png");
  } catch (const InputError& e) {
    m["error"] = e.what();
    spdlog::warn("published relations not scored: {}", e.what());
  }
}

void AddReferenceMapMetrics(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& reference_yaml,
                            const std::string& out, nlohmann::json& metrics) {
  const auto theirs = io::ReadRosMap(reference_yaml);
  const eval::MapAgreement a = eval::CompareMaps(grid, theirs);
  metrics["reference_map"] = eval::ToJson(a);
  metrics["reference_map"]["file"] = reference_yaml;
  spdlog::info(
      "against the reference map {}: {:.1f} % of our occupied cells within 0.1 m of its walls, {:.1f} % of its walls "
      "within 0.1 m of ours ({:.1f} % of those we saw)",
      reference_yaml, 100 * a.ours_within, 100 * a.theirs_within, 100 * a.theirs_within_seen);
  // The picture: the reference's grid as its background, occupied cells coloured.
  cv::Mat image(static_cast<int>(theirs.getSizeY()), static_cast<int>(theirs.getSizeX()), CV_8UC3,
                cv::Scalar(255, 255, 255));
  const auto row = [&](int cy) { return image.rows - 1 - cy; };
  for (int cy = 0; cy < image.rows; ++cy)
    for (int cx = 0; cx < image.cols; ++cx) {
      const float p_free = theirs.getCell(cx, cy);
      auto& px = image.at<cv::Vec3b>(row(cy), cx);
      if (p_free <= 0.35f)
        px = {60, 60, 220};  // their wall: red (BGR)
      else if (std::abs(p_free - 0.5f) < 0.01f)
        px = {205, 205, 205};  // unknown
    }
  for (unsigned cy = 0; cy < grid.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < grid.getSizeX(); ++cx) {
      if (grid.getCell(cx, cy) > 0.35f) continue;
      const auto p = a.ours_in_theirs + mrpt::poses::CPoint2D(grid.idx2x(cx), grid.idx2y(cy));
      const int ix = theirs.x2idx(p.x()), iy = theirs.y2idx(p.y());
      if (ix < 0 || iy < 0 || ix >= image.cols || iy >= image.rows) continue;
      auto& px = image.at<cv::Vec3b>(row(iy), ix);
      px = px == cv::Vec3b(60, 60, 220) ? cv::Vec3b(200, 40, 160) : cv::Vec3b(220, 90, 30);  // both: purple; ours: blue
    }
  io::WritePng(image, out + "/map_vs_reference.png");
}

// Mean map entropy of the keyframe scans at the estimated poses and, with a
// reference, of the same scans at the estimate's and at the reference's poses
// (eval/map_quality.h): whether the reference's map is sharper than ours.
void AddMapEntropy(const std::vector<slam::Keyframe>& keyframes, const Trajectory& reference, nlohmann::json& metrics) {
  const eval::MapEntropy ours = eval::MeanMapEntropy(keyframes);
  metrics["map_entropy"] = {{"mean_nats", ours.mean_nats}, {"points", ours.points}};
  if (reference.empty()) return;
  const auto [at_estimate, at_reference] = eval::KeyframesAtReference(keyframes, reference, 0.05);
  if (at_estimate.size() < 2) return;
  const eval::MapEntropy a = at_estimate.size() == keyframes.size() ? ours : eval::MeanMapEntropy(at_estimate);
  const eval::MapEntropy b = eval::MeanMapEntropy(at_reference);
  metrics["map_entropy_vs_reference"] = {
      {"keyframes", at_estimate.size()}, {"estimate_nats", a.mean_nats}, {"reference_nats", b.mean_nats}};
  spdlog::info(
      "map entropy: {:.3f} nats at the estimated poses, {:.3f} at the reference's ({} keyframes; lower is "
      "sharper)",
      a.mean_nats, b.mean_nats, at_estimate.size());
}

void WriteMapArtefact(const slam::GraphSlam& slam, const mrpt::maps::COccupancyGridMap2D& grid,
                      const std::string& out) {
  pipeline::WriteMapArtefact({slam.keyframes(), slam.graph(), grid, ""}, out);
}

// The loop closures as the final graph holds them (slam/pose_graph_optimizer.h's
// LoopResiduals): how many the robust loss keeps (weight ≥ 0.5), weakens, or sets
// aside (< 0.1: aliases, or matches off by far more than their noise); their errors;
// the worst by χ², named by their keyframes' scans; and loops.png, every loop drawn on
// the map in the colour of its weight.
void ReportLoops(const slam::GraphSlam& slam, const slam::PoseGraphOptions& options,
                 const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& trajectory, const std::string& out,
                 nlohmann::json& metrics) {
  std::vector<slam::LoopResidual> loops = slam::LoopResiduals(slam.graph(), options);
  const auto& keyframes = slam.keyframes();
  const auto& nodes = slam.graph().nodes;
  constexpr double kKeptWeight = 0.5, kSetAsideWeight = 0.1;
  Trajectory kept, weakened, set_aside;  // the loops' end poses in pairs, as PathOverlay segments
  std::vector<double> kept_m;
  for (const auto& l : loops) {
    Trajectory& group = l.weight >= kKeptWeight ? kept : l.weight >= kSetAsideWeight ? weakened : set_aside;
    for (int id : {l.from, l.to}) {
      const mrpt::poses::CPose2D& p = nodes.at(id);
      group.push_back({Stamp{}, mrpt::poses::CPose3D(p.x(), p.y(), 0, p.phi(), 0, 0)});
    }
    if (&group == &kept) kept_m.push_back(l.error_m);
  }
  std::sort(kept_m.begin(), kept_m.end());
  auto quantile = [&](double q) { return kept_m.empty() ? 0.0 : kept_m[static_cast<size_t>(q * (kept_m.size() - 1))]; };
  nlohmann::json j = {{"edges", loops.size()},
                      {"kept", kept.size() / 2},
                      {"weakened", weakened.size() / 2},
                      {"set_aside", set_aside.size() / 2},
                      {"kept_error_m", {{"p50", quantile(0.5)}, {"p95", quantile(0.95)}, {"max", quantile(1.0)}}}};
  std::sort(loops.begin(), loops.end(), [](const auto& a, const auto& b) { return a.chi2 > b.chi2; });
  nlohmann::json worst = nlohmann::json::array();
  for (size_t i = 0; i < std::min<size_t>(5, loops.size()); ++i) {
    const auto& l = loops[i];
    const auto scan = [&](int id) { return keyframes.at(static_cast<size_t>(id)).scan_index; };
    const auto t = [&](int id) { return keyframes.at(static_cast<size_t>(id)).stamp.Seconds(); };
    worst.push_back({{"from_scan", scan(l.from)},
                     {"to_scan", scan(l.to)},
                     {"t_from", t(l.from)},
                     {"t_to", t(l.to)},
                     {"error_m", l.error_m},
                     {"error_deg", l.error_deg},
                     {"weight", l.weight}});
  }
  j["worst"] = worst;
  metrics["loops"] = j;
  spdlog::info(
      "loops in the final graph: {} kept, {} weakened, {} set aside by the robust loss (kept: error p50 "
      "{:.3f} m, p95 {:.3f} m)",
      kept.size() / 2, weakened.size() / 2, set_aside.size() / 2, quantile(0.5), quantile(0.95));
  const std::vector<io::PathOverlay> paths = {
      {&trajectory, {30, 90, 220}, "estimate"},
      {&kept, {40, 170, 60}, "loop kept (" + std::to_string(kept.size() / 2) + ")", false, true},
      {&weakened, {240, 150, 0}, "loop weakened (" + std::to_string(weakened.size() / 2) + ")", false, true},
      {&set_aside, {220, 30, 30}, "loop set aside (" + std::to_string(set_aside.size() / 2) + ")", false, true}};
  io::WriteMapPng(grid, paths, out + "/loops.png");
}

}  // namespace specht::pipeline::internal
