#!/usr/bin/env bash
# How firm a SLAM figure is. Graph SLAM decides things by thresholds (keyframes, loop
# acceptance, which ICP start wins), so a change far below any tolerance — a gate
# moved by a centimetre, every loop's covariance widened by under 0.2 % — can flip
# one decision and the run goes on another way. One run is one draw: this runs
# `specht slam` on each CARMEN log at the point-to-line gates 0.09, 0.10 and 0.11 m
# (the default and a centimetre either side; SPREAD_GATES for others) and prints, per
# log, the relation error of each run and their mean, min and max, as one JSON object.
# Usage: bench/slam_spread.sh [build-dir] [-- specht slam args...]
#   e.g. bench/slam_spread.sh build/release -- --set loop_closure.max_candidates=6
# Logs: SPREAD_LOGS (default: intel freiburg-079 seattle freiburg-101 orebro).
# Gates: SPREAD_GATES (default: 0.09 0.10 0.11), e.g. "0.08 0.09 0.10 0.11 0.12".
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build/release
if [[ $# -gt 0 && $1 != "--" ]]; then build=$1; shift; fi
if [[ $# -gt 0 && $1 == "--" ]]; then shift; fi
data=${SPECHT_DATA_DIR:-$root/../shared/data}
logs=${SPREAD_LOGS:-intel freiburg-079 seattle freiburg-101 orebro}
read -r -a gates <<< "${SPREAD_GATES:-0.09 0.10 0.11}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

for log in $logs; do
  file=$data/slam/carmen/$log-corrected.log.gz
  if [[ ! -f $file ]]; then
    echo "slam_spread: $file not found (set SPECHT_DATA_DIR)" >&2
    exit 2
  fi
  pids=()
  for gate in "${gates[@]}"; do
    "$build/specht" slam -q "$file" -o "$work/$log-$gate" \
      --set "scan_matching.icp.point_to_line_gate_m=$gate" "$@" > "$work/$log-$gate.log" 2>&1 &
    pids+=($!)
  done
  for i in "${!gates[@]}"; do
    if ! wait "${pids[$i]}"; then
      echo "slam_spread: $log at gate ${gates[$i]} failed:" >&2
      tail -3 "$work/$log-${gates[$i]}.log" >&2
      exit 2
    fi
  done
  for gate in "${gates[@]}"; do
    jq -c --arg gate "$gate" '.metrics.relation.all | {gate_m: ($gate | tonumber), mean_m, max_m, mean_deg}' \
      "$work/$log-$gate/report.json"
  done | jq -s -c --arg name "slam-spread/$log" --arg args "$*" \
    '{name: $name, args: $args, runs: ., mean_m: (map(.mean_m) | add / length),
      min_m: (map(.mean_m) | min), max_m: (map(.mean_m) | max), max_relation_m: (map(.max_m) | max)}'
done
