#!/bin/bash
# Code comments say what and why; measured figures, benchmark timings, dataset scan
# numbers and the history of a choice belong in docs/*-experiments.md or the commit
# message, where they do not go stale when a default changes. This grep finds them in
# comments of the code that ships (modules/, apps/, bench/); comment_figures.allow
# lists the hits that are real constants ("path: fragment", one per line).
# Usage: check_comment_figures.sh REPO_ROOT
set -u
root=$1
cd "$root" || exit 1
allow=tests/docs/comment_figures.allow
pattern='(//|^ *#).*([0-9] ?(ms|s|m|%|°)? ?→ ?[0-9]|\bscans? [0-9]{2,}|\b[Mm]easured\b|\b(p50|p90|p95|p99) [0-9]|\bwas [0-9]|\b[0-9]+(\.[0-9]+)? ?(ms|µs) (a|per) (scan|frame|call|window|query))'
status=0
while IFS= read -r hit; do
  file=${hit%%:*}
  allowed=0
  while IFS= read -r entry; do
    [ -z "$entry" ] || [ "${entry:0:1}" = "#" ] && continue
    entry_file=${entry%%: *} fragment=${entry#*: }
    if [ "$entry_file" = "$file" ] && grep -qF -- "$fragment" <<<"$hit"; then allowed=1; break; fi
  done <"$allow"
  if [ $allowed = 0 ]; then
    echo "$hit"
    status=1
  fi
done < <(grep -rnE --include='*.cpp' --include='*.h' --include='*.sh' "$pattern" modules apps bench)
[ $status = 0 ] || echo "a figure or scan number in a code comment: move it to docs/*-experiments.md (or, if it is a real constant, to $allow)"
exit $status
