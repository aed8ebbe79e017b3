#!/usr/bin/env bash
# Checks that the C++ sources follow .clang-format (CTest test `format`; exit 77 = skipped where
# Debian 12's clang-format 14 is absent: other versions format differently). With --fix, formats
# them in place instead.
#   scripts/format_check.sh [--fix]
set -euo pipefail
cd "$(dirname "$0")/.."
tool=""
for t in clang-format-14 clang-format; do
  if command -v "$t" >/dev/null && "$t" --version | grep -q 'version 14\.'; then tool=$t; break; fi
done
[ -n "$tool" ] || { echo "format_check: clang-format 14 not found: skipped"; exit 77; }
mapfile -t files < <(git ls-files -- 'src/*.cpp' 'src/*.h' 'tests/*.cpp' 'tests/*.h' \
                       'include/*.h' 'examples/*.cpp' 'shaders/*.h' 'bench/*.cpp' 'python/*.cpp' \
                       'python/*.h' \
                       ':!tests/data/*')
if [ "${1:-}" = "--fix" ]; then
  "$tool" -i "${files[@]}"
  exit 0
fi
if ! "$tool" --dry-run -Werror "${files[@]}" 2> /tmp/format_check.$$; then
  grep -E '^[^ ]+:[0-9]+:[0-9]+: error' /tmp/format_check.$$ | cut -d: -f1 | sort -u |
    sed 's/^/format_check: not formatted: /'
  rm -f /tmp/format_check.$$
  echo "format_check: run scripts/format_check.sh --fix (clang-format 14, .clang-format)"
  exit 1
fi
rm -f /tmp/format_check.$$
echo "format_check: ${#files[@]} files formatted"
