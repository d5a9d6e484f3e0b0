// specht/eval/mot.h: CLEAR MOT metrics (Bernardin & Stiefelhagen 2008) for tracks in
// the map plane.
//
// Frames are the distinct times of truth and hypotheses (to the millisecond). In each
// frame a truth object keeps the hypothesis it was matched to in the previous frame
// when that one is still within match_threshold_m; the rest are matched by optimal
// assignment on distance (core/assignment.h), pairs farther than the threshold
// forbidden. A truth object matched to a different hypothesis than at its last match
// is an identity switch. Then
//   MOTA = 1 − (FN + FP + IDSW) / GT          (GT: truth objects summed over frames)
//   MOTP = Σ d(match) / matches               (metres, lower is better)
// Track-seconds are truth object-frames times the median frame interval; ID switches
// are also given per 100 track-seconds. Mostly tracked / lost: truth objects matched in
// ≥ 80 % / < 20 % of their frames; a fragmentation is a tracked → untracked → tracked
// interruption. Truth rows marked ignore (don't care) are matched last: a hypothesis
// on one is neither a match nor a false positive, and a missed one is not a miss.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/io/object_tracks.h"

namespace specht::eval {

struct MotResult {
  long frames = 0, truth_objects = 0, matches = 0;
  long false_negatives = 0, false_positives = 0, id_switches = 0, fragmentations = 0;
  int truth_ids = 0, hypothesis_ids = 0, mostly_tracked = 0, mostly_lost = 0;
  double mota = 0, motp_m = 0, distance_sum_m = 0;
  double track_seconds = 0, id_switches_per_100s = 0;
  // Each hypothesis id → the truth id it was matched to most often.
  std::map<std::string, std::string> truth_of_hypothesis;

  // Sums the counts of another evaluation (a separate run) and recomputes the rates.
  void Add(const MotResult& other);
  nlohmann::json ToJson() const;
};

MotResult EvaluateMot(const std::vector<io::ObjectSample>& truth, const std::vector<io::ObjectSample>& hypotheses,
                      double match_threshold_m);

}  // namespace specht::eval
