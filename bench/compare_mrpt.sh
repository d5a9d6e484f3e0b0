#!/usr/bin/env bash
# Side by side with MRPT's own icp-slam and graphslam-engine (Debian mrpt-apps) on the same data: the
# Radish CARMEN logs and MRPT's simulated rawlogs with ground truth, each converted
# with `specht convert --layout frames` (one action/sensory-frame pair per scan,
# actions time-stamped: icp-slam refuses MRPT's own demo rawlogs, whose actions carry
# no stamps).
# Both trajectories are scored by `specht eval slam` against the same reference.
# icp-slam runs with its shipped demo configuration (icp-slam_demo_classic.ini),
# headless. graphslam-engine runs through its engine class (bench/mrpt_graphslam.cpp: the
# app's default deciders CICPCriteriaNRD/ERD + CLevMarqGSO, its shipped laser_odometry.ini),
# which stamps every scan; the app itself writes only an unstamped graph.
# Prints one JSON object per dataset. Usage: bench/compare_mrpt.sh [build-dir]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build/release}
specht=$build/specht
data=${SPECHT_DATA_DIR:-$root/../shared/data}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mrpt_ini=/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_classic.ini
graphslam_ini=/usr/share/mrpt/config_files/graphslam-engine/laser_odometry.ini

# relation error over all relations from a specht report, and the wall time, as JSON
figures() {
  jq -c --argjson wall "$2" '.metrics.relation.all |
    {relation_mean_m: .mean_m, relation_max_m: .max_m, relation_mean_deg: .mean_deg, wall_s: $wall}' "$1"
}
seconds_since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN {printf "%.2f", b - a}'; }

compare() {  # name rawlog reference [specht args...]
  local name=$1 rawlog=$2 reference=$3 dir=$work/$1
  shift 3
  mkdir -p "$dir"
  local t0=$(date +%s.%N)
  "$specht" slam -q "$rawlog" --ground-truth "$reference" -o "$dir/specht" "$@" >/dev/null 2>&1
  local specht_s=$(seconds_since "$t0")
  local t1=$(date +%s.%N)
  sed -e "s|^rawlog_file=.*|rawlog_file=$rawlog|" -e 's|^SHOW_PROGRESS_3D_REAL_TIME=1|SHOW_PROGRESS_3D_REAL_TIME=0|' \
      -e 's|^SAVE_3D_SCENE=1|SAVE_3D_SCENE=0|' -e 's|^LOG_FREQUENCY=50|LOG_FREQUENCY=1000000|' \
      -e "s|^logOutput_dir=.*|logOutput_dir=$dir/icp|" "$mrpt_ini" > "$dir/icp.ini"
  if ! (cd "$dir" && icp-slam icp.ini >"$dir/icp.log" 2>&1); then
    printf '{"name":"compare_mrpt/%s","mrpt_icp_slam":{"failed":"%s"}}\n' "$name" \
      "$(grep -m1 'Message:' "$dir/icp.log" | sed 's/"/\\"/g')"
    return
  fi
  local icp_s=$(seconds_since "$t1")
  # icp-slam logs one pose per step (= per scan, in order): stamp it like specht's.
  grep -v '^#' "$dir/specht/trajectory.tum" | awk '{print $1}' > "$dir/stamps"
  paste -d' ' "$dir/stamps" <(awk '{printf "%s %s %s\n", $2, $3, $4}' "$dir/icp/log_estimated_path.txt") |
    awk 'NF==4 {printf "%s %s %s 0 0 0 %.9f %.9f\n", $1, $2, $3, sin($4/2), cos($4/2)}' > "$dir/icp.tum"
  "$specht" eval slam --estimate "$dir/icp.tum" --reference "$reference" -o "$dir/icp-eval" >/dev/null
  local t2=$(date +%s.%N)
  "$build/bench/mrpt_graphslam" "$graphslam_ini" "$rawlog" "$dir/graphslam.tum" >"$dir/graphslam.log" 2>&1
  local graphslam_s=$(seconds_since "$t2")
  "$specht" eval slam --estimate "$dir/graphslam.tum" --reference "$reference" -o "$dir/graphslam-eval" >/dev/null
  printf '{"name":"compare_mrpt/%s","specht":%s,"mrpt_icp_slam":%s,"mrpt_graphslam_engine":%s}\n' "$name" \
    "$(figures "$dir/specht/report.json" "$specht_s")" "$(figures "$dir/icp-eval/report.json" "$icp_s")" \
    "$(figures "$dir/graphslam-eval/report.json" "$graphslam_s")"
}

demos=/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map
for f in simul range_030_bearing_015; do
  "$specht" convert -q "$demos/$f.rawlog" -o "$work/$f.rawlog" --layout frames
  compare "mrpt-$f" "$work/$f.rawlog" "$demos/$f.rawlog.GT.txt"
done
compare "mrpt-range_030_bearing_015-noisy-preset" "$work/range_030_bearing_015.rawlog" \
  "$demos/range_030_bearing_015.rawlog.GT.txt" -p "$root/params/noisy-laser.yaml"
if [[ -d "$data/slam/carmen" ]]; then
  for f in intel freiburg-079 seattle orebro freiburg-101; do
    log=$data/slam/carmen/$f-corrected.log.gz
    "$specht" convert -q "$log" -o "$work/$f.rawlog" --layout frames
    compare "carmen-$f" "$work/$f.rawlog" "$log"
  done
fi
