#!/usr/bin/env bash
# Re-measures every row of the README's results table, one capability after the
# other, and prints one JSON object per row (also saved to OUT/results.jsonl; each
# row's own outputs stay in OUT/<row>/). Run it on an idle machine: it took 65
# minutes on the reference 2-core machine on a slow day (AIS 21 of them).
# Usage: bench/results.sh [OUT (default build/release/results)] [row...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SPECHT_BUILD:-$root/build/release}
specht=$build/specht
data=${SPECHT_DATA_DIR:-$root/../shared/data}
out=${1:-$build/results}
shift || true
rows=("$@")
[[ ${#rows[@]} -gt 0 ]] || rows=(stereo pose_graph planning simulator detection freiburg radish perception tracking classification ais closed_loop tuning)
mkdir -p "$out"
S=("$root"/datasets/scenarios/{urban-crossing,course-loop,parking-lot}.yaml)
emit() { tee -a "$out/results.jsonl"; }
row() { echo "results: $1" >&2; }

freiburg() {
  for log in intel fr079 aces; do
    "$specht" slam -q "$data/slam/freiburg/$log.clf.bz2" -o "$out/freiburg/$log" > /dev/null
    jq -c --arg log "$log" '{row: "freiburg", log: $log, relation: .metrics.published_relations,
      real_time_factor: .timing.real_time_factor, peak_rss_mib: .timing.peak_rss_mib}' "$out/freiburg/$log/report.json" | emit
  done
}
radish() { "$root/bench/compare_mrpt.sh" "$build" | jq -c '{row: "radish"} + .' | emit; }
pose_graph() { "$build/bench/pose_graph_bench" "$data"/slam/g2o/{intel,CSAIL,manhattan,city10000}.g2o | jq -c '{row: "pose_graph"} + .' | emit; }
stereo() { "$build/bench/stereo_bench" "$data" | jq -c '{row: "stereo"} + .' | emit; }
detection() {
  "$build/bench/detect_bench" "$data" | jq -c '{row: "detection"} + .' | emit
  SPECHT_DATA_DIR=$data "$build/tests/detect_test" --gtest_filter='*Fusion*:*Lidar*:*HandBox*:*Kitti*' 2>&1 |
    grep -E "median|found|cars|OK|FAILED" | jq -R -c '{row: "detection", test_output: .}' | emit
}
perception() { "$root/bench/perception_eval.sh" 101-101 30 | jq -c '{row: "perception"} + .' | emit; }
tracking() {
  "$specht" track -q "${S[@]}" --seeds 6-25 -o "$out/tracking" > /dev/null
  jq -c '{row: "tracking", mot: .metrics}' "$out/tracking/report.json" | emit
}
classification() {
  local d=$out/classification
  "$specht" track -q "${S[@]}" --seeds 1-20 -o "$d/train-tracks" > /dev/null
  "$specht" track -q "${S[@]}" --seeds 21-30 -o "$d/test-tracks" > /dev/null
  local scen=(); for s in "${S[@]}"; do scen+=(--scenario "$s"); done
  for x in train test; do "$specht" classify prepare -q "$d/$x-tracks/tracks.csv" "${scen[@]}" -o "$d/$x-data" > /dev/null; done
  "$specht" classify train -q "$d/train-data" -o "$d/model" > /dev/null
  "$specht" classify eval -q "$d/model" "$d/test-data" -o "$d/eval" > /dev/null
  jq -c '{row: "classification", metrics: .metrics}' "$d/eval/report.json" | emit
}
ais() {
  local d=$out/ais
  "$specht" ais prepare -q "$data"/ais/tracks/{brest,mpa}-dev.csv.gz --data-dir "$data" -o "$d/ais60" > /dev/null
  "$specht" ais eval -q "$d/ais60" --folds 5 --networks tiny -o "$d/cv" > /dev/null
  jq -c '{row: "ais", models: (.models | map_values({macro_f1: .macro_f1, weighted_f1: .weighted_f1})), paired: .paired}' "$d/cv/report.json" | emit
}
planning() { "$build/bench/plan_bench" --quick "${S[@]}" | jq -c '{row: "planning"} + .' | emit; }
closed_loop() {
  for s in parking-lot urban-crossing course-loop; do
    "$specht" run -q "$root/datasets/scenarios/$s.yaml" --seeds 1-20 -o "$out/closed_loop/$s" > /dev/null || true
    jq -c --arg s "$s" '{row: "closed_loop", scenario: $s, metrics: .metrics}' "$out/closed_loop/$s/report.json" | emit
  done
}
tuning() {
  local d=$out/tuning k=$data/stereo/kitti2015
  "$specht" tune -q "$root/params/tune/stereo-kitti.yaml" --data-dir "$data" -j 2 -o "$d/tune" > /dev/null
  jq -c '{row: "tuning", metrics: .metrics, timing: .timing}' "$d/tune/report.json" | emit
  for p in default best; do
    local args=(); [[ $p = best ]] && args=(-p "$d/tune/best.yaml")
    "$specht" stereo -q "$k/image_2/000000_10.png" "$k/image_3/000000_10.png" "${args[@]}" -o "$d/$p-000000" > /dev/null
    "$specht" eval stereo --estimate "$d/$p-000000/disparity.png" --truth "$k/disp_occ_0/000000_10.png" --fill-holes \
      -o "$d/$p-000000-eval" > /dev/null
    jq -c --arg p "$p" '{row: "tuning", frame: "000000", params: $p, d1_all: .metrics.d1_all}' "$d/$p-000000-eval/report.json" | emit
  done
}
simulator() { "$build/bench/sim_bench" --sprites "$data/sprites" "${S[@]}" | jq -c '{row: "simulator"} + .' | emit; }

for r in "${rows[@]}"; do
  row "$r"
  start=$(date +%s)
  "$r"
  echo "{\"row\": \"$r\", \"wall_s\": $(( $(date +%s) - start ))}" | emit
done
echo "results: $out/results.jsonl" >&2
