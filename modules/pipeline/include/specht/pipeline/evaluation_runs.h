// specht/pipeline/evaluation_runs.h: scoring outputs against ground truth — what
// `specht eval slam|stereo|track` run. Each writes report.json and its pictures into
// `out_dir` and prints the figures.
#pragma once

#include <string>

#include "specht/eval/relation_error.h"

namespace specht::pipeline {

// An estimated trajectory (TUM) against a reference (a corrected CARMEN log, TUM or
// "t x y theta": relation error, Kümmerle et al. 2009, and ATE after SE(2) alignment,
// trajectories.png) and/or a published relations file (every relation matched by
// stamp; relations.png with the worst, on `map_yaml` when given).
struct SlamEvaluationInputs {
  std::string estimate, reference, relations_file, map_yaml;
  eval::RelationOptions relations;
  eval::PublishedRelationOptions published;
};
int EvaluateSlam(const SlamEvaluationInputs& in, const std::string& out_dir);

// D1, bad-2, end-point error and density of a disparity PNG (KITTI uint16, or 8-bit
// Middlebury × truth_scale) on all ground-truth pixels and on the estimated ones,
// with coloured disparity and error pictures.
struct StereoEvaluationInputs {
  std::string estimate, truth, exclude;  // exclude: pixels set in this disparity PNG are not scored
  double truth_scale = 1.0;
  bool fill_holes = false;  // fill missing estimates row-wise first (KITTI's rule)
};
int EvaluateStereo(const StereoEvaluationInputs& in, const std::string& out_dir);

// CLEAR MOT (eval/mot.h) of tracks against ground truth, both io/object_tracks.h CSV.
int EvaluateTracks(const std::string& truth_csv, const std::string& tracks_csv, double match_threshold_m,
                   const std::string& out_dir);

}  // namespace specht::pipeline
