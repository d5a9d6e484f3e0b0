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
#include "commands.h"
#include "specht/pipeline/evaluation_runs.h"

namespace specht::app {
namespace {

struct EvalSlamArgs {
  pipeline::SlamEvaluationInputs in;
  std::string out_dir = "specht-out/eval-slam";
};

struct EvalStereoArgs {
  pipeline::StereoEvaluationInputs in;
  std::string out_dir = "specht-out/eval-stereo";
};

struct EvalTrackArgs {
  std::string truth, tracks;
  double match_threshold_m = 1.0;
  std::string out_dir = "specht-out/eval-track";
};

}  // namespace

void AddEvalCommand(CLI::App& app, int& exit_code) {
  CLI::App* eval = app.add_subcommand("eval", "evaluate outputs against ground truth");
  eval->require_subcommand(1);
  auto args = std::make_shared<EvalSlamArgs>();
  CLI::App* slam = eval->add_subcommand("slam", "relation error (Kuemmerle et al. 2009) and ATE of a trajectory");
  slam->add_option("--estimate", args->in.estimate, "estimated trajectory (TUM)")->required();
  slam->add_option("--reference", args->in.reference, "corrected CARMEN log, TUM or 't x y theta' reference");
  slam->add_option("--relations", args->in.relations_file,
                   "published relations file (t1 t2 x y z roll pitch yaw, Kuemmerle et al. 2009): every relation "
                   "must match the estimate by stamp");
  slam->add_option("--relations-max-dt", args->in.published.max_dt_s,
                   "a relation's stamps match the estimate's within this (s)")
      ->capture_default_str();
  slam->add_option("--map", args->in.map_yaml, "draw the worst relations on this map (map_server YAML)");
  slam->add_option("-o,--out", args->out_dir, "output directory")->capture_default_str();
  slam->add_option("--loop-distance", args->in.relations.loop_max_distance_m,
                   "loop relations: reference poses closer than this (m)")
      ->capture_default_str();
  slam->add_option("--loop-separation", args->in.relations.loop_min_separation,
                   "loop relations: more than this many scans apart")
      ->capture_default_str();
  slam->add_option("--worst", args->in.relations.worst_count, "list this many relations with the largest error")
      ->capture_default_str();
  slam->add_option("--max-dt", args->in.relations.max_dt_s, "pair poses whose stamps differ by at most this (s)")
      ->capture_default_str();
  slam->callback([args, &exit_code] { exit_code = pipeline::EvaluateSlam(args->in, args->out_dir); });

  auto stereo_args = std::make_shared<EvalStereoArgs>();
  CLI::App* st = eval->add_subcommand("stereo", "D1, bad-2, end-point error and density of a disparity map");
  st->add_option("--estimate", stereo_args->in.estimate, "estimated disparity (KITTI uint16 PNG)")->required();
  st->add_option("--truth", stereo_args->in.truth, "ground truth (KITTI uint16, or 8-bit Middlebury)")->required();
  st->add_option("--truth-scale", stereo_args->in.truth_scale, "8-bit ground truth: disparity per grey level")
      ->capture_default_str();
  st->add_flag("--fill-holes", stereo_args->in.fill_holes, "fill missing estimates row-wise first (KITTI's rule)");
  st->add_option("--exclude", stereo_args->in.exclude,
                 "do not score pixels set in this disparity PNG (e.g. the hints)");
  st->add_option("-o,--out", stereo_args->out_dir, "output directory")->capture_default_str();
  st->callback(
      [stereo_args, &exit_code] { exit_code = pipeline::EvaluateStereo(stereo_args->in, stereo_args->out_dir); });

  auto track_args = std::make_shared<EvalTrackArgs>();
  CLI::App* tr = eval->add_subcommand("track", "CLEAR MOT (MOTA, MOTP, ID switches) of tracks against ground truth");
  tr->add_option("--truth", track_args->truth, "ground truth CSV (id,t_s,x_m,y_m)")->required();
  tr->add_option("--tracks", track_args->tracks, "tracker output CSV (id,t_s,x_m,y_m)")->required();
  tr->add_option("--match-threshold", track_args->match_threshold_m, "a match is at most this far (m)")
      ->capture_default_str();
  tr->add_option("-o,--out", track_args->out_dir, "output directory")->capture_default_str();
  tr->callback([track_args, &exit_code] {
    exit_code = pipeline::EvaluateTracks(track_args->truth, track_args->tracks, track_args->match_threshold_m,
                                         track_args->out_dir);
  });

  AddEvalPerceptionCommand(*eval, exit_code);
}

}  // namespace specht::app
