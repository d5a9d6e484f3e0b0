#!/usr/bin/env bash
# Runs every libFuzzer target (tests/fuzz, built by `cmake --build --preset fuzz`)
# for a bounded time on seed corpora cut from real files: the data directory's logs,
# graphs, AIS feeds and calibrations, MRPT's shipped rawlogs and specht's own
# parameter, scenario, mission and tune files. Seeds are the first 16 KB of each file
# (libFuzzer mutates short inputs far faster); the corpora live in a scratch folder,
# never in the project. Two targets run at a time (one per core; SPECHT_FUZZ_JOBS).
#
#   scripts/fuzz.sh [seconds per target, default 30] [target ...]
#
# SPECHT_FUZZ_RUNS=N makes each target a campaign of N executions (10000000 for the
# long ones), which may run in segments: a segment ends at the time bound or on
# Ctrl-C, and the next run with the same SPECHT_FUZZ_DIR resumes from its corpus with
# the executions still owed. Each target's folder keeps campaign.tsv, a row per run
# (end time, seed, executions, coverage, seconds, how it ended), and its logs
# (log-<row>.txt). SPECHT_FUZZ_MAX_LEN caps an input's bytes (default 16384; shorter
# inputs run faster). ASAN_OPTIONS passes through (a campaign may trade allocation
# stack traces for speed: docs/testing.md).
#
# A finding (crash, sanitizer report, an exception that is not specht's own error)
# fails the script; its reproducer is kept in $SPECHT_FUZZ_DIR/<target>/ (crash-*),
# to become a regression test in the ordinary suite.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-30}
shift || true
bin="$root/build/fuzz/tests/fuzz"
data=${SPECHT_DATA_DIR:-$root/../shared/data}
work=${SPECHT_FUZZ_DIR:-$(mktemp -d /tmp/specht-fuzz.XXXXXX)}
mrpt=/usr/share/mrpt/datasets

# seed <target> <file>...: the first 16 KB of each file (decompressed) as a seed.
seed() {
  local target=$1
  shift
  mkdir -p "$work/$target/seeds"
  for f in "$@"; do
    [[ -f "$f" ]] || continue
    local name
    name=$(basename "$f")
    case "$f" in
      *.gz) (zcat "$f" 2>/dev/null || true) | head -c 16384 > "$work/$target/seeds/$name" ;;
      *.bz2) (bzcat "$f" 2>/dev/null || true) | head -c 16384 > "$work/$target/seeds/$name" ;;
      *) head -c 16384 "$f" > "$work/$target/seeds/$name" ;;
    esac
  done
}

seed fuzz_rawlog "$mrpt"/*.rawlog "$data"/slam/freiburg/*.rawlog
seed fuzz_carmen "$data"/slam/carmen/*.log.gz "$data"/slam/freiburg/*.clf.bz2
seed fuzz_g2o "$data"/slam/g2o/*.g2o "$mrpt"/graph_2d_circle_50nodes.graph
seed fuzz_trajectory "$mrpt"/*ground_truth*.txt "$data"/slam/carmen/intel-corrected.log.gz "$data"/slam/freiburg/intel.relations
seed fuzz_nmea "$data"/ais/nmea/*.log "$data"/ais/nmea/*.aivdm
seed fuzz_ais_positions "$data"/ais/tracks/*.csv.gz
seed fuzz_params "$root"/params/*.yaml "$root"/params/tune/*.yaml
seed fuzz_scenario "$root"/datasets/scenarios/*.yaml "$root"/datasets/missions/*.yaml "$root"/params/launch/*.yaml
seed fuzz_calibration "$data"/stereo/kitti_object/calib.txt
seed fuzz_ros_messages "$data"/ros/*/*.db3

targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
  for t in "$bin"/fuzz_*; do targets+=("$(basename "$t")"); done
fi

# executions_in <log>: what a libFuzzer log says it ran: the larger of its final
# statistics and its last progress line (a run killed prints no statistics; a
# fork-mode parent prints its own, which count none of its jobs' executions).
executions_in() {
  local stats progress
  stats=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$1" | grep -o '[0-9]*$' | tail -1 || true)
  progress=$(grep -o '^#[0-9]*' "$1" | tail -1 | tr -d '#' || true)
  echo $((${stats:-0} > ${progress:-0} ? ${stats:-0} : ${progress:-0}))
}

# coverage_in <log>: the edges the log's last status line reports.
coverage_in() { grep -o 'cov: [0-9]*' "$1" | tail -1 | grep -o '[0-9]*' || echo '?'; }

# record <dir> <seconds> <end>: the folder's log.txt as a row of campaign.tsv (its
# number in $recorded), the log kept beside it as log-<row>.txt.
record() {
  local dir=$1 ledger="$1/campaign.tsv" seed
  [[ -f $ledger ]] || printf 'row\tended\tseed\texecutions\tcoverage\tseconds\tend\n' > "$ledger"
  recorded=$(($(wc -l < "$ledger")))
  seed=$(grep -o -m1 'INFO: Seed: [0-9]*' "$dir/log.txt" | grep -o '[0-9]*$' || echo '?')
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$recorded" "$(date -u -r "$dir/log.txt" +%FT%TZ)" "$seed" \
    "$(executions_in "$dir/log.txt")" "$(coverage_in "$dir/log.txt")" "$2" "$3" >> "$ledger"
  mv "$dir/log.txt" "$dir/log-$recorded.txt"
}

# campaign_executions <dir>: the executions of every row so far.
campaign_executions() {
  awk -F'\t' 'NR > 1 { n += $4 } END { print n + 0 }' "$1/campaign.tsv" 2>/dev/null || echo 0
}

run() {
  # A stop reaches every process of the script's group as INT and TERM: a fork-mode
  # parent ignores INT while its job runs, and this shell must live to record the run.
  trap '' TERM
  local t=$1 dir="$work/$1"
  mkdir -p "$dir/corpus" "$dir/seeds" "$dir/tmp"
  # Targets that parse a path write each input to a scratch file; a process killed on a
  # finding (fork mode goes on past them) leaves its file in this folder, not in /tmp.
  # The folder is on tmpfs (/dev/shm) when there is one, and then goes when the target
  # ends (the reproducer is the crash-* file): rewriting a file on ext4 costs a fifth
  # of fuzz_carmen's time (truncate, open, close; 1,250 → 1,670 executions/s).
  local scratch="$dir/tmp"
  if [[ -d /dev/shm && -w /dev/shm ]]; then
    scratch=$(mktemp -d "/dev/shm/specht-fuzz-$t.XXXXXX")
    trap 'rm -rf "$scratch"' RETURN
  fi
  export TMPDIR="$scratch"
  # -rss_limit_mb: a bounded parser on bounded input; -timeout: no input may hang it.
  # MRPT's deserializer sizes strings and containers from the record's 32-bit counts
  # before reading them, so a corrupt rawlog record may allocate and fill gigabytes
  # before it fails (cleanly, as a DatasetError): an upstream limit, not ours.
  # Filling those takes seconds and gigabytes: that target runs in libFuzzer's fork
  # mode, which counts out-of-memory and slow inputs and goes on. A count too large
  # to allocate at all throws std::bad_alloc in the release build (the reader turns
  # it into a DatasetError) but is fatal under ASan, whose operator new never throws;
  # the target's own operator new throws as the release build's does, but MRPT's
  # aligned allocator goes around it (tests/fuzz/fuzz_rawlog.cpp). Fork mode goes on
  # past crashes too, and each crash it kept is replayed below; only that allocation
  # failure is no finding. Leak checking is off in fork mode: a
  # job ended by the memory limit once hung in LeakSanitizer's stop-the-world (its
  # tracer waiting on a lock for 45 min, 2026-12-06), and the fork-mode parent waits
  # on its jobs without bound; the reader's own leaks are ASan's unit tests' to find.
  local mode=()
  [[ $t == fuzz_rawlog ]] && mode=(-fork=1 -ignore_ooms=1 -ignore_timeouts=1 -ignore_crashes=1 -detect_leaks=0)
  # Whatever hangs, the stage ends: a run past its time by 5 minutes is killed, and
  # counts as a finding (it did not reach its end). In the foreground: the fuzzer
  # stays in this script's process group, where Ctrl-C reaches it.
  local bound=(timeout --foreground -k 10 $((seconds + 300)))
  # -seed: the same mutations every run (SPECHT_FUZZ_SEED to explore others), so a
  # CI run does not turn red on a finding another run missed by chance. -print_funcs=0:
  # no symbolizer naming each newly covered function (Ctrl-C ends it too, and the
  # fork-mode parent then died of SIGPIPE instead of stopping).
  local rc=0
  local runs=() start=$SECONDS
  # A log no row holds is a run stopped before it was recorded (Ctrl-C, a kill).
  [[ -f $dir/log.txt ]] && record "$dir" '?' stopped
  if [[ -n "${SPECHT_FUZZ_RUNS:-}" ]]; then
    local owed=$((SPECHT_FUZZ_RUNS - $(campaign_executions "$dir")))
    if [[ $owed -le 0 ]]; then
      echo "fuzz: $t: campaign complete, $(campaign_executions "$dir") executions ($dir/campaign.tsv)"
      return 0
    fi
    runs=(-runs="$owed")
  fi
  (cd "$dir" && "${bound[@]}" "$bin/$t" "${mode[@]}" "${runs[@]}" -seed="${SPECHT_FUZZ_SEED:-1}" -max_total_time="$seconds" -max_len="${SPECHT_FUZZ_MAX_LEN:-16384}" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 -print_funcs=0 corpus seeds > log.txt 2>&1) || rc=$?
  # Fork mode exits with the last job's code even when it ignored it (libFuzzer 14),
  # and copies a failed job's log (sanitizer report included) into ours. Its verdict
  # is therefore the replay of every input it kept as a crash or a leak: one that is
  # not an unallocatable count is a finding. A run that did not reach its end is one
  # too.
  # Stopped by Ctrl-C or TERM: the script's trap leaves a mark (a fork-mode parent's
  # exit code then depends on where its job was); libFuzzer alone exits 72 or 130.
  local stopped=0
  [[ -e $work/.stop || $rc -eq 72 || $rc -eq 130 ]] && stopped=1 && rc=0
  local unallocatable=0
  if [[ ${#mode[@]} -gt 0 ]] && { [[ $stopped -eq 1 ]] || grep -q "^INFO: exiting:" "$dir/log.txt"; }; then
    rc=0
    for kept in "$dir"/crash-* "$dir"/leak-*; do
      [[ -e $kept ]] || continue
      if ("$bin/$t" "$kept" 2>&1 || true) | grep -qE "SUMMARY: AddressSanitizer: (out-of-memory|allocation-size-too-big)"; then
        unallocatable=$((unallocatable + 1))
      else
        rc=1
        echo "fuzz: $t: $kept fails when replayed" >> "$dir/log.txt"
      fi
    done
  fi
  local execs cov skipped campaign=''
  execs=$(executions_in "$dir/log.txt")
  cov=$(coverage_in "$dir/log.txt")
  skipped=$(grep -o 'oom/timeout/crash: [0-9/]*' "$dir/log.txt" | tail -1 || true)
  [[ $unallocatable -gt 0 ]] && skipped="${skipped:+$skipped, }$unallocatable unallocatable counts"
  if [[ $rc -eq 0 ]]; then
    local end=finished
    [[ $stopped -eq 1 ]] && end=stopped
    record "$dir" $((SECONDS - start)) $end
    [[ -n "${SPECHT_FUZZ_RUNS:-}" ]] && campaign="; campaign: $(campaign_executions "$dir") of $SPECHT_FUZZ_RUNS"
    echo "fuzz: $t: $execs executions in $((SECONDS - start)) s, coverage $cov edges, no finding${skipped:+ ($skipped)}, $end$campaign"
  else
    record "$dir" $((SECONDS - start)) finding
    echo "fuzz: $t: FINDING (see $dir/log-$recorded.txt; reproducer in $dir)" >&2
    tail -40 "$dir/log-$recorded.txt" >&2
    return 1
  fi
}

# Ctrl-C or TERM stops every target at once: each fuzzer prints what it ran, which is
# recorded as a stopped row (a campaign resumes from its corpus), and the script
# exits 130. The targets' own shells ignore it (they run in the background).
interrupted=0
rm -f "$work/.stop"
trap 'interrupted=1; touch "$work/.stop"; trap "" INT TERM; kill -INT 0; kill -TERM 0' INT TERM

failed=0
pids=()
for t in "${targets[@]}"; do
  [[ $interrupted -eq 1 ]] && break
  run "$t" &
  pids+=($!)
  if [[ ${#pids[@]} -ge ${SPECHT_FUZZ_JOBS:-2} ]]; then
    wait "${pids[0]}" || failed=1
    pids=("${pids[@]:1}")
  fi
done
for p in "${pids[@]}"; do wait "$p" || failed=1; done
# A signal breaks a wait off early: the targets still record what they ran.
while [[ -n $(jobs -pr) ]]; do wait || true; done
[[ $interrupted -eq 1 ]] && exit 130
[[ "${SPECHT_FUZZ_DIR:-}" ]] || { [[ $failed -eq 0 ]] && rm -rf "$work"; }
exit $failed
