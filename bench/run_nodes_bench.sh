#!/usr/bin/env bash
# `specht run --nodes` against the in-process run (issue 60): each shipped scenario's
# mission over a few seeds, full stack, once in one process and once with the stack
# as `specht node stack` over DDS in lockstep. Prints one JSON object per scenario:
# whether every run's success and collisions agree, the largest distance between the
# two runs' poses at any control step and at the end, and the latency between the
# processes per control step — until the stack acknowledged the step's inputs (a
# step's messages delivered), and from the question to the decision (transport and
# the stack's own work: planning steps take longer) — p50 / p99 / max over the runs,
# and both real-time factors. With "perception" as the third argument the tracker runs
# as a third process (`--perception-node`); the perception frames written into the
# world model on both sides show whether every frame's tracks came back, and the
# stack's round trip to the perception node (pose out, tracks back) is the worst
# drive's p50 / p99 / max.
# Usage: bench/run_nodes_bench.sh [seeds, default 101-103] [DDS domain, default 230] [stack|perception]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
specht=${SPECHT_BINARY:-$root/build/release/specht}
seeds=${1:-101-103}
domain=${2:-230}
split=${3:-stack}
nodes=(--nodes)
[ "$split" = perception ] && nodes+=(--perception-node)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for scenario in course-loop parking-lot urban-crossing; do
  run=("$specht" run "$root/datasets/scenarios/$scenario.yaml" --seeds "$seeds" -q --set closed_loop.mcap=off)
  "${run[@]}" --set closed_loop.video=off -o "$work/$scenario-here" > /dev/null || true
  "${run[@]}" "${nodes[@]}" --domain "$domain" -o "$work/$scenario-nodes" > /dev/null || true
  steps=$(for f in "$work/$scenario-here"/steps-*.jsonl; do
    jq -c -n --slurpfile a "$f" --slurpfile b "$work/$scenario-nodes/$(basename "$f")" \
      '[range(0; [$a, $b] | map(length) | min) | ((($a[.].x_m - $b[.].x_m) | . * .) + (($a[.].y_m - $b[.].y_m) | . * .)) | sqrt] |
       {max: max, last: last, same_length: (($a | length) == ($b | length))}'
  done | jq -s -c '.')
  # The stack's round trip to the perception node per detector frame, from each stack node's report.
  round_trip=$(cat "$work/$scenario-nodes"/stack-*/report.json | jq -s -c 'map(.perception_node.answer_ms // empty) |
    if length == 0 then null else {p50: (map(.p50) | max), p99: (map(.p99) | max), max: (map(.max) | max)} end')
  jq -c -n --slurpfile here "$work/$scenario-here/report.json" --slurpfile nodes "$work/$scenario-nodes/report.json" \
    --argjson round_trip "$round_trip" \
    --argjson steps "$steps" --arg scenario "$scenario" --arg seeds "$seeds" --arg split "$split" '
    ($here[0].runs) as $a | ($nodes[0].runs) as $b |
    {bench: "run_nodes", case: $scenario, split: $split, seeds: $seeds, runs: ($a | length),
     same_success_and_collisions: ([range(0; $a | length) | $a[.].success == $b[.].success and
                                    $a[.].collisions == $b[.].collisions] | all),
     same_step_count: ($steps | map(.same_length) | all),
     max_step_difference_m: ($steps | map(.max) | max), max_final_difference_m: ($steps | map(.last) | max),
     acknowledged_ms: $nodes[0].metrics.nodes.acknowledged_ms, answer_ms: $nodes[0].metrics.nodes.answer_ms,
     real_time_factor_here: $here[0].metrics.real_time_factor,
     real_time_factor_nodes: $nodes[0].metrics.real_time_factor,
     perception_frames_here: ([$a[].perception.frames] | add),
     perception_frames_nodes: ([$b[].perception.frames] | add),
     perception_round_trip_ms_worst_drive: $round_trip}'
done
