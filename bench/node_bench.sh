#!/usr/bin/env bash
# The SLAM node (`specht node slam`) keeping up with a 40 Hz, 1080-beam scan stream
# over DDS on this machine's loopback, as separate processes: a simulated drive on
# the course (its LiDAR at 40 Hz with 1080 beams over 270°, odometry at 50 Hz, no
# camera) written by `specht sim`, played at real time by `specht node play`
# (reliable), mapped by the node, which publishes /map every second of data. Prints
# one JSON object: scans published and mapped (loss), how long messages waited
# between arrival and use (p50 / p99 / max: a node slower than the stream shows as a
# growing wait), the node's ms per scan, its map messages and peak memory.
# Usage: bench/node_bench.sh [seconds of drive, default 60] [DDS domain, default 231]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
specht=${SPECHT_BINARY:-$root/build/release/specht}
seconds=${1:-60}
domain=${2:-231}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e 's/lidar: {rate_hz: 10, beams: 361/lidar: {rate_hz: 40, beams: 1080/' -e '/^ *stereo:/d' \
  "$root/datasets/scenarios/course-loop.yaml" > "$work/course-40hz.yaml"
grep -q "rate_hz: 40, beams: 1080" "$work/course-40hz.yaml" || { echo "node_bench: the scenario's LiDAR line changed" >&2; exit 1; }
"$specht" sim -q "$work/course-40hz.yaml" --duration "$seconds" -o "$work/sim" > /dev/null
"$specht" node slam -q --no-mcap --idle-end 3 --domain "$domain" -o "$work/node" > /dev/null 2>&1 &
node=$!
"$specht" node play -q "$work/sim/sim.rawlog" --rate 1 --domain "$domain" -o "$work/play" > /dev/null
wait "$node"
jq -c -n --slurpfile play "$work/play/report.json" --slurpfile node "$work/node/report.json" --argjson s "$seconds" '
  ($play[0].counts.published["/scan"]) as $sent | ($node[0].counts.scans) as $got |
  {bench: "node", case: "slam_node_40hz_1080_beams", drive_s: $s, scans_published: $sent, scans_mapped: $got,
   loss_percent: (100 * ($sent - $got) / $sent), waited_ms: $node[0].input_figures,
   slam_ms_per_scan: $node[0].timing.ms_per_scan, map_messages: $node[0].published.messages["/map"],
   loops_accepted: $node[0].counts.loops_accepted, peak_rss_mib: $node[0].timing.peak_rss_mib,
   player_real_time_factor: $play[0].timing.real_time_factor}'
