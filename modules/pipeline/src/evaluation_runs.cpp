// Scoring a run's outputs against ground truth (evaluation_runs.h): what `specht
// eval slam|stereo|track` run.
#include "specht/pipeline/evaluation_runs.h"

#include <cstdio>
#include <opencv2/core.hpp>

#include "internal/map_outputs.h"
#include "specht/core/error.h"
#include "specht/eval/disparity_error.h"
#include "specht/eval/mot.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/object_tracks.h"
#include "specht/io/reference.h"
#include "specht/io/report.h"
#include "specht/io/trajectory_io.h"
#include "specht/stereo/images.h"
#include "specht/stereo/sgm.h"

namespace specht::pipeline {
namespace {

void PrintPublished(const eval::PublishedRelationError& rel) {
  const auto& a = rel.absolute;
  const auto& q = rel.squared;
  std::printf("published relations %zu (all matched)\n", rel.relations);
  std::printf("  absolute  %.4f ± %.4f m (max %.4f)   %.3f ± %.3f deg (max %.3f)\n", a.mean_m, a.std_m, a.max_m,
              a.mean_deg, a.std_deg, a.max_deg);
  std::printf("  squared   %.5f ± %.5f m²            %.3f ± %.3f deg²\n", q.mean_m, q.std_m, q.mean_deg, q.std_deg);
  std::printf("worst published relations (scan i, j: stamps, error)\n");
  for (const eval::Relation& r : rel.worst) {
    std::printf("  %6zu %6zu   %.6f s %.6f s   %.4f m   %.3f deg\n", r.i, r.j, r.stamp_i.Seconds(), r.stamp_j.Seconds(),
                r.m, r.deg);
  }
}

// The published relations: metrics and relations.png (the worst relations on the map).
void EvalPublishedRelations(const SlamEvaluationInputs& a, const Trajectory& estimate, const std::string& out,
                            io::RunReport& report) {
  eval::PublishedRelationOptions options = a.published;
  options.worst_count = a.relations.worst_count;
  const eval::PublishedRelationError rel =
      eval::ComputePublishedRelationError(estimate, io::ReadRelations(a.relations_file), options);
  report.json()["metrics"]["published_relations"] = eval::ToJson(rel);
  const Trajectory worst = eval::RelationSegments(estimate, rel.worst);
  const std::vector<io::PathOverlay> overlays = internal::RelationOverlays(estimate, worst, rel.worst.size());
  if (a.map_yaml.empty()) {
    io::WriteTrajectoryPng(overlays, out + "/relations.png");
  } else {
    io::WriteMapPng(io::ReadRosMap(a.map_yaml), overlays, out + "/relations.png");
  }
  report.AddOutput("relations.png");
  PrintPublished(rel);
}

}  // namespace

int EvaluateSlam(const SlamEvaluationInputs& a, const std::string& out) {
  if (a.reference.empty() && a.relations_file.empty()) {
    throw InputError("eval slam: give --reference (a trajectory) or --relations (a relations file), or both");
  }
  const Trajectory estimate = io::ReadTum(a.estimate);
  io::RunReport report("eval slam");
  auto& j = report.json();
  j["inputs"] = {{"estimate", a.estimate}, {"reference", a.reference}, {"relations", a.relations_file}};
  io::MakeOutputDir(out);
  if (!a.relations_file.empty()) EvalPublishedRelations(a, estimate, out, report);
  if (a.reference.empty()) {
    report.Write(out);
    return 0;
  }
  const Trajectory reference = io::ReadReference(a.reference);
  const eval::RelationError rel = eval::ComputeRelationError(estimate, reference, a.relations);
  const eval::AteResult ate = eval::AbsoluteTrajectoryError2D(estimate, reference, a.relations.max_dt_s);
  j["metrics"]["relation"] = eval::ToJson(rel);
  j["metrics"]["ate"] = eval::ToJson(ate);
  const Trajectory aligned = eval::Transform(estimate, ate.alignment);
  io::WriteTrajectoryPng({{&reference, {40, 170, 60}, "reference"}, {&aligned, {30, 90, 220}, "estimate (aligned)"}},
                         out + "/trajectories.png");
  report.AddOutput("trajectories.png");
  report.Write(out);

  std::printf("relations       count   mean±std m          max m    mean±std deg      max deg\n");
  for (const auto& [name, s] : {std::pair{"consecutive", rel.consecutive}, {"loop", rel.loop}, {"all", rel.all}}) {
    std::printf("%-12s %8zu   %.4f ± %.4f   %8.4f   %6.3f ± %6.3f   %7.3f\n", name, s.count, s.mean_m, s.std_m, s.max_m,
                s.mean_deg, s.std_deg, s.max_deg);
  }
  std::printf("ATE (SE(2)-aligned, %zu poses): RMSE %.4f m, max %.4f m, %.3f deg RMSE\n", ate.pairs, ate.rmse_m,
              ate.max_m, ate.rmse_deg);
  if (!rel.worst.empty()) std::printf("worst relations (scan i, j: stamps, kind, error)\n");
  for (const eval::Relation& r : rel.worst) {
    std::printf("  %6zu %6zu   %.3f s %.3f s   %-11s   %.4f m   %.3f deg\n", r.i, r.j, r.stamp_i.Seconds(),
                r.stamp_j.Seconds(), r.loop ? "loop" : "consecutive", r.m, r.deg);
  }
  return 0;
}

int EvaluateStereo(const StereoEvaluationInputs& a, const std::string& out) {
  cv::Mat estimate = stereo::ReadDisparityPng(a.estimate);
  const cv::Mat truth = stereo::ReadDisparityPng(a.truth, a.truth_scale);
  if (estimate.size() != truth.size())
    throw InputError(a.estimate + ": " + std::to_string(estimate.cols) + "×" + std::to_string(estimate.rows) +
                     " differs from the ground truth's " + std::to_string(truth.cols) + "×" +
                     std::to_string(truth.rows));
  cv::Mat mask;
  if (!a.exclude.empty()) {
    const cv::Mat excluded = stereo::ReadDisparityPng(a.exclude);
    if (excluded.size() != truth.size()) throw InputError(a.exclude + ": size differs from the ground truth");
    mask = excluded <= 0;
  }
  if (a.fill_holes) stereo::FillHolesRowwise(estimate);
  const eval::DisparityErrors e = eval::CompareDisparity(estimate, truth, mask);
  io::MakeOutputDir(out);
  io::RunReport report("eval stereo");
  report.json()["inputs"] = {
      {"estimate", a.estimate}, {"truth", a.truth}, {"fill_holes", a.fill_holes}, {"excluded", a.exclude}};
  report.json()["metrics"] = eval::ToJson(e);
  double max_disparity = 0;
  cv::minMaxLoc(truth, nullptr, &max_disparity);
  io::WritePng(eval::DisparityErrorImage(estimate, truth), out + "/error.png");
  io::WritePng(stereo::ColorizeDisparity(estimate, max_disparity), out + "/estimate_color.png");
  io::WritePng(stereo::ColorizeDisparity(truth, max_disparity), out + "/truth_color.png");
  for (const char* f : {"error.png", "estimate_color.png", "truth_color.png"}) report.AddOutput(f);
  report.Write(out);
  std::printf("pixels with ground truth %zu, estimated %zu (density %.1f %%)\n", e.gt_pixels, e.est_pixels,
              100 * e.density_gt);
  std::printf("all:       D1 %.2f %%  bad-2 %.2f %%\n", 100 * e.d1_all, 100 * e.bad2_all);
  std::printf("estimated: D1 %.2f %%  bad-2 %.2f %%  EPE %.3f px\n", 100 * e.d1_est, 100 * e.bad2_est, e.epe_est);
  return 0;
}

int EvaluateTracks(const std::string& truth_csv, const std::string& tracks_csv, double match_threshold_m,
                   const std::string& out) {
  const auto truth = io::ReadObjectTracks(truth_csv);
  if (truth.empty()) throw InputError(truth_csv + ": no truth rows (only a header): nothing to score against");
  const auto tracks = io::ReadObjectTracks(tracks_csv);
  const eval::MotResult mot = eval::EvaluateMot(truth, tracks, match_threshold_m);
  io::MakeOutputDir(out);
  io::RunReport report("eval track");
  report.json()["inputs"] = {{"truth", truth_csv}, {"tracks", tracks_csv}, {"match_threshold_m", match_threshold_m}};
  report.json()["metrics"] = mot.ToJson();
  report.Write(out);
  std::printf("MOTA %.4f  MOTP %.3f m  ID switches %ld (%.2f per 100 track-s)  FP %ld  FN %ld  GT %ld\n", mot.mota,
              mot.motp_m, mot.id_switches, mot.id_switches_per_100s, mot.false_positives, mot.false_negatives,
              mot.truth_objects);
  std::printf("truth ids %d: mostly tracked %d, mostly lost %d, fragmentations %ld; hypothesis ids %d\n", mot.truth_ids,
              mot.mostly_tracked, mot.mostly_lost, mot.fragmentations, mot.hypothesis_ids);
  return 0;
}

}  // namespace specht::pipeline
