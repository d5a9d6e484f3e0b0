// `specht eval slam --estimate traj.tum --reference REF`: relation error (Kümmerle et
// al. 2009) and ATE of an estimated trajectory against a reference, with a plot.
// REF is a corrected CARMEN log (its laser poses), a TUM file or a "t x y theta" file.
// `--relations FILE` scores it on a published relations file instead (or as well),
// with a picture of the worst relations (on `--map map.yaml` when given).
//
// `specht eval track --truth truth.csv --tracks tracks.csv`: CLEAR MOT (eval/mot.h).
//
// `specht eval stereo --estimate disp.png --truth gt.png [--fill-holes] [--exclude
// hints.png]`: D1, bad-2, end-point error and density (eval/disparity_error.h) on all
// ground-truth pixels and on the estimated ones, with coloured disparity and error
// pictures. Disparity PNGs: KITTI uint16, or 8-bit Middlebury (× --truth-scale).
#include <cstdio>
#include <iostream>
#include <opencv2/core.hpp>

#include "commands.h"
#include "run_setup.h"
#include "specht/core/error.h"
#include "specht/eval/disparity_error.h"
#include "specht/eval/mot.h"
#include "specht/eval/relation_error.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/object_tracks.h"
#include "specht/io/reference.h"
#include "specht/io/report.h"
#include "specht/io/trajectory_io.h"
#include "specht/stereo/images.h"
#include "specht/stereo/sgm.h"

namespace specht::app {
namespace {

struct EvalSlamArgs {
  std::string estimate;
  std::string reference;
  std::string relations_file;
  std::string map_yaml;
  std::string out_dir = "specht-out/eval-slam";
  eval::RelationOptions relations;
  eval::PublishedRelationOptions published;
};

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
void EvalPublishedRelations(const EvalSlamArgs& a, const Trajectory& estimate, io::RunReport& report) {
  eval::PublishedRelationOptions options = a.published;
  options.worst_count = a.relations.worst_count;
  const eval::PublishedRelationError rel =
      eval::ComputePublishedRelationError(estimate, io::ReadRelations(a.relations_file), options);
  report.json()["metrics"]["published_relations"] = eval::ToJson(rel);
  const Trajectory worst = eval::RelationSegments(estimate, rel.worst);
  const std::vector<io::PathOverlay> overlays{
      {&estimate, {30, 90, 220}, "estimate"},
      {&worst, {220, 30, 30}, "the " + std::to_string(rel.worst.size()) + " worst relations", false, true}};
  if (a.map_yaml.empty()) {
    io::WriteTrajectoryPng(overlays, a.out_dir + "/relations.png");
  } else {
    io::WriteMapPng(io::ReadRosMap(a.map_yaml), overlays, a.out_dir + "/relations.png");
  }
  report.AddOutput("relations.png");
  PrintPublished(rel);
}

int RunEvalSlam(const EvalSlamArgs& a) {
  if (a.reference.empty() && a.relations_file.empty()) {
    throw InputError("eval slam: give --reference (a trajectory) or --relations (a relations file), or both");
  }
  const Trajectory estimate = io::ReadTum(a.estimate);
  io::RunReport report("eval slam");
  auto& j = report.json();
  j["inputs"] = {{"estimate", a.estimate}, {"reference", a.reference}, {"relations", a.relations_file}};
  io::MakeOutputDir(a.out_dir);
  if (!a.relations_file.empty()) EvalPublishedRelations(a, estimate, report);
  if (a.reference.empty()) {
    report.Write(a.out_dir);
    return 0;
  }
  const Trajectory reference = io::ReadReference(a.reference);
  const eval::RelationError rel = eval::ComputeRelationError(estimate, reference, a.relations);
  const eval::AteResult ate = eval::AbsoluteTrajectoryError2D(estimate, reference, a.relations.max_dt_s);
  j["metrics"]["relation"] = eval::ToJson(rel);
  j["metrics"]["ate"] = eval::ToJson(ate);
  const Trajectory aligned = eval::Transform(estimate, ate.alignment);
  io::WriteTrajectoryPng({{&reference, {40, 170, 60}, "reference"}, {&aligned, {30, 90, 220}, "estimate (aligned)"}},
                         a.out_dir + "/trajectories.png");
  report.AddOutput("trajectories.png");
  report.Write(a.out_dir);

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

struct EvalStereoArgs {
  std::string estimate, truth, exclude;
  double truth_scale = 1.0;
  bool fill_holes = false;
  std::string out_dir = "specht-out/eval-stereo";
};

int RunEvalStereo(const EvalStereoArgs& a) {
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
  io::MakeOutputDir(a.out_dir);
  io::RunReport report("eval stereo");
  report.json()["inputs"] = {
      {"estimate", a.estimate}, {"truth", a.truth}, {"fill_holes", a.fill_holes}, {"excluded", a.exclude}};
  report.json()["metrics"] = eval::ToJson(e);
  double max_disparity = 0;
  cv::minMaxLoc(truth, nullptr, &max_disparity);
  io::WritePng(eval::DisparityErrorImage(estimate, truth), a.out_dir + "/error.png");
  io::WritePng(stereo::ColorizeDisparity(estimate, max_disparity), a.out_dir + "/estimate_color.png");
  io::WritePng(stereo::ColorizeDisparity(truth, max_disparity), a.out_dir + "/truth_color.png");
  for (const char* f : {"error.png", "estimate_color.png", "truth_color.png"}) report.AddOutput(f);
  report.Write(a.out_dir);
  std::printf("pixels with ground truth %zu, estimated %zu (density %.1f %%)\n", e.gt_pixels, e.est_pixels,
              100 * e.density_gt);
  std::printf("all:       D1 %.2f %%  bad-2 %.2f %%\n", 100 * e.d1_all, 100 * e.bad2_all);
  std::printf("estimated: D1 %.2f %%  bad-2 %.2f %%  EPE %.3f px\n", 100 * e.d1_est, 100 * e.bad2_est, e.epe_est);
  return 0;
}

struct EvalTrackArgs {
  std::string truth, tracks;
  double match_threshold_m = 1.0;
  std::string out_dir = "specht-out/eval-track";
};

int RunEvalTrack(const EvalTrackArgs& a) {
  const auto truth = io::ReadObjectTracks(a.truth);
  if (truth.empty()) throw InputError(a.truth + ": no truth rows (only a header): nothing to score against");
  const auto tracks = io::ReadObjectTracks(a.tracks);
  const eval::MotResult mot = eval::EvaluateMot(truth, tracks, a.match_threshold_m);
  io::MakeOutputDir(a.out_dir);
  io::RunReport report("eval track");
  report.json()["inputs"] = {{"truth", a.truth}, {"tracks", a.tracks}, {"match_threshold_m", a.match_threshold_m}};
  report.json()["metrics"] = mot.ToJson();
  report.Write(a.out_dir);
  std::printf("MOTA %.4f  MOTP %.3f m  ID switches %ld (%.2f per 100 track-s)  FP %ld  FN %ld  GT %ld\n", mot.mota,
              mot.motp_m, mot.id_switches, mot.id_switches_per_100s, mot.false_positives, mot.false_negatives,
              mot.truth_objects);
  std::printf("truth ids %d: mostly tracked %d, mostly lost %d, fragmentations %ld; hypothesis ids %d\n", mot.truth_ids,
              mot.mostly_tracked, mot.mostly_lost, mot.fragmentations, mot.hypothesis_ids);
  return 0;
}

}  // namespace

void AddEvalCommand(CLI::App& app, int& exit_code) {
  CLI::App* eval = app.add_subcommand("eval", "evaluate outputs against ground truth");
  eval->require_subcommand(1);
  auto args = std::make_shared<EvalSlamArgs>();
  CLI::App* slam = eval->add_subcommand("slam", "relation error (Kuemmerle et al. 2009) and ATE of a trajectory");
  slam->add_option("--estimate", args->estimate, "estimated trajectory (TUM)")->required();
  slam->add_option("--reference", args->reference, "corrected CARMEN log, TUM or 't x y theta' reference");
  slam->add_option("--relations", args->relations_file,
                   "published relations file (t1 t2 x y z roll pitch yaw, Kuemmerle et al. 2009): every relation "
                   "must match the estimate by stamp");
  slam->add_option("--relations-max-dt", args->published.max_dt_s,
                   "a relation's stamps match the estimate's within this (s)")
      ->capture_default_str();
  slam->add_option("--map", args->map_yaml, "draw the worst relations on this map (map_server YAML)");
  slam->add_option("-o,--out", args->out_dir, "output directory")->capture_default_str();
  slam->add_option("--loop-distance", args->relations.loop_max_distance_m,
                   "loop relations: reference poses closer than this (m)")
      ->capture_default_str();
  slam->add_option("--loop-separation", args->relations.loop_min_separation,
                   "loop relations: more than this many scans apart")
      ->capture_default_str();
  slam->add_option("--worst", args->relations.worst_count, "list this many relations with the largest error")
      ->capture_default_str();
  slam->add_option("--max-dt", args->relations.max_dt_s, "pair poses whose stamps differ by at most this (s)")
      ->capture_default_str();
  slam->callback([args, &exit_code] { exit_code = RunEvalSlam(*args); });

  auto stereo_args = std::make_shared<EvalStereoArgs>();
  CLI::App* st = eval->add_subcommand("stereo", "D1, bad-2, end-point error and density of a disparity map");
  st->add_option("--estimate", stereo_args->estimate, "estimated disparity (KITTI uint16 PNG)")->required();
  st->add_option("--truth", stereo_args->truth, "ground truth (KITTI uint16, or 8-bit Middlebury)")->required();
  st->add_option("--truth-scale", stereo_args->truth_scale, "8-bit ground truth: disparity per grey level")
      ->capture_default_str();
  st->add_flag("--fill-holes", stereo_args->fill_holes, "fill missing estimates row-wise first (KITTI's rule)");
  st->add_option("--exclude", stereo_args->exclude, "do not score pixels set in this disparity PNG (e.g. the hints)");
  st->add_option("-o,--out", stereo_args->out_dir, "output directory")->capture_default_str();
  st->callback([stereo_args, &exit_code] { exit_code = RunEvalStereo(*stereo_args); });

  auto track_args = std::make_shared<EvalTrackArgs>();
  CLI::App* tr = eval->add_subcommand("track", "CLEAR MOT (MOTA, MOTP, ID switches) of tracks against ground truth");
  tr->add_option("--truth", track_args->truth, "ground truth CSV (id,t_s,x_m,y_m)")->required();
  tr->add_option("--tracks", track_args->tracks, "tracker output CSV (id,t_s,x_m,y_m)")->required();
  tr->add_option("--match-threshold", track_args->match_threshold_m, "a match is at most this far (m)")
      ->capture_default_str();
  tr->add_option("-o,--out", track_args->out_dir, "output directory")->capture_default_str();
  tr->callback([track_args, &exit_code] { exit_code = RunEvalTrack(*track_args); });

  AddEvalPerceptionCommand(*eval, exit_code);
}

}  // namespace specht::app
