#!/usr/bin/env bash
# The perception-timeout fault across nodes (issue 60): `specht run --nodes
# --perception-node` on the course, its perception node killed (SIGKILL) a few wall
# seconds into each drive. Prints one JSON object per drive: when the run saw the
# node gone (drive time), how long after that the car stopped (`blind`), when it
# drove on, the simulated seconds it stood, the frames without tracks, and whether
# the mission still completed without a collision.
# Usage: bench/perception_fault_bench.sh [seeds, default 101-103] [kill after S wall seconds, default 2]
#        [DDS domain, default 231]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
specht=${SPECHT_BINARY:-$root/build/release/specht}
seeds=${1:-101-103}
after=${2:-2}
domain=${3:-231}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for seed in $(seq "${seeds%-*}" "${seeds#*-}"); do
  out="$work/$seed"
  "$specht" run "$root/datasets/scenarios/course-loop.yaml" --seeds "$seed" -q --nodes --perception-node \
    --domain "$domain" --set closed_loop.mcap=off -o "$out" > /dev/null 2>&1 &
  run=$!
  for _ in $(seq 300); do [ -f "$out/perception-$seed/params.yaml" ] && break; sleep 0.1; done
  sleep "$after"
  pkill -KILL -f -- "[-]o $out/perception-$seed" || true
  wait "$run" || true
  jq -c --slurpfile stack "$out/stack-$seed/report.json" --arg seed "$seed" '.runs[0] as $r |
    ($r.nodes.perception_node.restarts[0].gone_at_s // null) as $gone |
    ([$r.transitions[] | select($gone != null and .to == "blind" and .t_s >= $gone)][0].t_s // null) as $blind |
    ([$r.transitions[] | select($blind != null and .from == "blind" and .t_s > $blind)][0].t_s // null) as $back |
    {bench: "perception_fault", scenario: "course-loop", seed: ($seed | tonumber), gone_at_s: $gone,
     stopped_after_s: (if $blind then $blind - $gone else null end), drove_on_at_s: $back,
     stood_s: (if $back then $back - $blind else null end),
     frames_without_tracks: $stack[0].perception_node.missing, restarts: ($r.nodes.perception_node.restarts | length),
     success: $r.success, collisions: $r.collisions}' "$out/report.json"
done
