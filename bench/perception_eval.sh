#!/usr/bin/env bash
# Perception on simulated drives, against the simulator's truth: for each scenario
# and seed, `specht sim` with the held-out sprites, `specht eval perception` (both
# detectors), `specht replay` (the whole pipeline: SLAM, SGM, detector, fusion,
# tracker, world model) and the perceived tracks scored. Prints one JSON object per
# drive. Usage: bench/perception_eval.sh [seeds (default 101-103)] [seconds (default 30)] [model]
# With a model (a `specht classify train` output) the replay classifies the tracks
# online and the class F1 of the classifier and of the combination are printed too.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
specht=${SPECHT_BINARY:-$root/build/release/specht}
data=${SPECHT_DATA_DIR:-$root/../shared/data}
seeds=${1:-101-103}
seconds=${2:-30}
model_args=()
if [[ -n "${3:-}" ]]; then model_args=(--model "$3"); fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for scenario in course-loop urban-crossing parking-lot; do
  for seed in $(seq "${seeds%-*}" "${seeds#*-}"); do
    d=$work/$scenario-$seed
    "$specht" sim -q "$root/datasets/scenarios/$scenario.yaml" --seed "$seed" --duration "$seconds" \
      --data-dir "$data" --sprites held_out -o "$d/sim" > /dev/null
    "$specht" replay -q "$d/sim/sim.rawlog" --data-dir "$data" "${model_args[@]}" -o "$d/replay" > /dev/null 2>&1
    "$specht" eval perception "$d/sim" --replay "$d/replay" --data-dir "$data" -q -o "$d/eval" > /dev/null
    jq -c --arg s "$scenario" --argjson seed "$seed" --slurpfile r "$d/replay/report.json" '{
        name: ("perception/" + $s + "/" + ($seed|tostring)),
        detection: (.metrics.detection | map_values({recall: .all.recall, precision: .all.precision,
          any_class_recall: .any_class.recall, fp_per_frame: .false_positives_per_frame,
          per_class: (.per_class | map_values({truth, recall})), recall_by_range,
          distance_p50_m: .distance_abs_error_m.p50})),
        tracks: {mota: .metrics.tracks.mot.mota, id_switches_per_100s: .metrics.tracks.mot.id_switches_per_100s,
          class_f1_detector_vote: .metrics.tracks.class_detector_vote.macro_f1,
          class_f1_classifier: .metrics.tracks.class_classifier.macro_f1,
          class_f1_combined: .metrics.tracks.class_combined.macro_f1, tracks_classified: .metrics.tracks.class_classifier.tracks,
          tracks_scored: .metrics.tracks.class_detector_vote.tracks, slam_ate_m: .metrics.tracks.slam_ate_rmse_m},
        pipeline: {real_time_factor: $r[0].timing.real_time_factor, peak_rss_mib: $r[0].timing.peak_rss_mib,
          ms_per_frame: $r[0].perception.ms_per_frame}}' \
      "$d/eval/report.json"
  done
done
