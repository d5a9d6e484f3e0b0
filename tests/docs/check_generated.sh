#!/bin/bash
# docs/cli.md and docs/params.md are what `specht commands --markdown` and
# `specht params --markdown` print; fails with the diff when either is stale.
# Usage: check_generated.sh SPECHT_BINARY REPO_ROOT
set -u
specht=$1 root=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
"$specht" commands --markdown >"$tmp/cli.md" || { echo "specht commands --markdown failed"; exit 1; }
"$specht" params --markdown >"$tmp/params.md" || { echo "specht params --markdown failed"; exit 1; }
for page in cli params; do
  generator="specht commands --markdown"
  [ "$page" = params ] && generator="specht params --markdown"
  if ! diff -u "$root/docs/$page.md" "$tmp/$page.md"; then
    echo "docs/$page.md is stale: regenerate it with \`build/release/$generator > docs/$page.md\`"
    status=1
  fi
done
exit $status
