#!/usr/bin/env bash
# Runs every benchmark and prints one JSON object per case (also saved to
# build/release/bench-results.jsonl). Usage: bench/run.sh [build-dir]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build/release}
out=$build/bench-results.jsonl
: > "$out"
run() { "$@" | tee -a "$out"; }

mrpt=/usr/share/mrpt/datasets
run "$build/bench/point_index_bench"
run "$build/bench/slam_bench" "$mrpt/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog" builtin-telecom-faculty
for f in simul range_030_bearing_015; do
  run "$build/bench/slam_bench" "$mrpt/graphslam-engine-demos/action_observations_map/$f.rawlog" "mrpt-$f"
done
data=${SPECHT_DATA_DIR:-$root/../shared/data}
if [[ -d "$data/slam/carmen" ]]; then
  for f in intel freiburg-079 seattle orebro freiburg-101; do
    run "$build/bench/slam_bench" "$data/slam/carmen/$f-corrected.log.gz" "carmen-$f"
  done
fi
if [[ -d "$data/slam/freiburg" ]]; then
  for f in intel fr079 aces fr-clinic_robotlaser; do
    run "$build/bench/slam_bench" "$data/slam/freiburg/$f.clf.bz2" "freiburg-$f"
  done
fi
if [[ -d "$data/slam/g2o" ]]; then
  run "$build/bench/pose_graph_bench" "$data"/slam/g2o/{intel,CSAIL,manhattan,city10000}.g2o
fi
if [[ -d "$data/stereo" ]]; then
  run "$build/bench/stereo_bench" "$data"
  run "$build/bench/detect_bench" "$data"
fi
sprites=()
[[ -d "$data/sprites" ]] && sprites=(--sprites "$data/sprites")
run "$build/bench/sim_bench" "${sprites[@]}" "$root"/datasets/scenarios/{course-loop,urban-crossing,parking-lot}.yaml
run "$build/bench/track_bench" "$root"/datasets/scenarios/{course-loop,urban-crossing,parking-lot}.yaml
camera=()
[[ -d "$data/sprites" ]] && camera=(--data "$data")
run "$build/bench/loop_bench" "${camera[@]}" "$root"/datasets/scenarios/{course-loop,urban-crossing,parking-lot}.yaml
run "$build/bench/classify_bench"
if [[ -d "$data/ais" ]]; then
  run "$build/bench/ais_bench" "$data"
fi
if [[ -d "$data/ros" ]]; then
  run "$build/bench/bag_bench" "$data"
fi
run "$build/bench/plan_bench" "$root"/datasets/scenarios/{course-loop,urban-crossing,parking-lot}.yaml
run "$build/bench/dds_bench"
run "$build/bench/sim_node_bench" "$build/specht"
SPECHT_BINARY=$build/specht run "$root/bench/node_bench.sh"
SPECHT_BINARY=$build/specht run "$root/bench/run_nodes_bench.sh"
SPECHT_BINARY=$build/specht run "$root/bench/run_nodes_bench.sh" 101-103 230 perception
SPECHT_BINARY=$build/specht run "$root/bench/perception_fault_bench.sh"
echo "bench: results in $out" >&2
