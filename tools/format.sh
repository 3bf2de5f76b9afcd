#!/usr/bin/env bash
# Formats every tracked C++ and Java file with .clang-format, or with --check says which differ and fails.
# Debian 12's clang-format is version 14; the tree is formatted by that version.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.java')
if [[ "${1:-}" == "--check" ]]; then
  report=$(mktemp)
  trap 'rm -f "$report"' EXIT
  if ! clang-format --dry-run -Werror "${files[@]}" 2>"$report"; then
    grep -o '^[^:]*:[0-9]*:[0-9]*: error' "$report" | cut -d: -f1 | sort -u |
      sed 's/^/format.sh: not formatted: /' >&2
    echo "format.sh: run ./tools/format.sh to format them" >&2
    exit 1
  fi
  echo "format.sh: ${#files[@]} files formatted"
else
  clang-format -i "${files[@]}"
fi
