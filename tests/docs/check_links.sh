#!/bin/bash
# Every relative link and image in README.md and docs/*.md points at a file that
# exists, and every page of docs/ is linked from the README.
# Usage: check_links.sh REPO_ROOT
set -u
root=$1
cd "$root" || exit 1
status=0
for page in README.md docs/*.md; do
  dir=$(dirname "$page")
  # Markdown links and images, "](target" with the line number grep gives them.
  while IFS=: read -r line_no match; do
    target=${match#](}
    case "$target" in http://* | https://* | mailto:* | \#*) continue ;; esac
    file=${target%%#*}
    if [ ! -e "$dir/$file" ]; then
      echo "$page:$line_no: broken link '$target' (no file $dir/$file)"
      status=1
    fi
  done < <(grep -onE '\]\([^) ]+' "$page")
done
for page in docs/*.md; do
  if ! grep -q "](${page})\|](${page}#" README.md; then
    echo "README.md: no link to $page (every page of docs/ is reached from the front door)"
    status=1
  fi
done
exit $status
