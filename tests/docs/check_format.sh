#!/bin/bash
# The C++ sources follow the root .clang-format (Debian 12's clang-format 14; other
# versions format some constructs differently). Fix with
#   git ls-files '*.cpp' '*.h' | xargs clang-format-14 -i
# Usage: check_format.sh REPO_ROOT
set -u
root=$1
cd "$root" || exit 1
tool=$(command -v clang-format-14 || command -v clang-format) || {
  echo "clang-format not found: scripts/setup.sh installs it"
  exit 1
}
bad=()
while IFS= read -r -d '' file; do
  "$tool" --dry-run -Werror "$file" >/dev/null 2>&1 || bad+=("$file")
done < <(find apps bench modules tests \( -name '*.cpp' -o -name '*.h' \) -print0 | sort -z)
if [ ${#bad[@]} -gt 0 ]; then
  for file in "${bad[@]}"; do echo "$file: not formatted ($tool --dry-run $file shows how)"; done
  echo "${#bad[@]} file(s) differ from .clang-format: $tool -i <file>"
  exit 1
fi
