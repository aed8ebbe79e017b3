#!/usr/bin/env bash
# The CPU-native yardstick (bench/yardstick/yardstick.cpp) shades what tileshade shades: on a tiny
# street/many dump (96x54, seconds), serial and threaded, and on its metallic-roughness + spot +
# sun variant, its image agrees with the `tiled` image of the same dump and with the double
# reference to fp32 rounding (2e-6 of the peak: ten times what this build gives here, a tenth of
# the fp32 bound of docs/accuracy.md), and the same check fails against another frame's image.
#   tests/bench/yardstick_test.sh TILESHADE_BINARY YARDSTICK_BINARY
set -euo pipefail
ts="${1:?tileshade binary}"
ys="${2:?yardstick binary}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
dump() {  # frame folder [render options]
  "$ts" render --scene builtin:street --lights many --width 96 --height 54 --frame "$1" \
    --technique tiled --device cpu --dump --out "$2" "${@:3}" > "$work/render.log" ||
    { cat "$work/render.log"; exit 1; }
}
dump 30 "$work/a"
dump 0 "$work/b"
# The other paths of the model: metallic-roughness, spot lights (cone culling), a directional light.
dump 30 "$work/c" --variant metallic-roughness,spot,sun
for run in "a 1" "a 2" "c 2"; do
  # shellcheck disable=SC2086  # "DUMP THREADS", meant to split
  set -- $run
  "$ys" "$work/$1" --runs 1 --threads "$2" --reference --compare "$work/$1/image.exr" \
    --max-error 2e-6 > "$work/ys.log" || { cat "$work/ys.log"; echo "FAIL: $run"; exit 1; }
  cat "$work/ys.log"
  # Culling ran and listed lights; both comparisons were made.
  grep -q "lights listed per tile" "$work/ys.log"
  listed=$(sed -n 's/.*; \([0-9.]*\) lights listed per tile/\1/p' "$work/ys.log")
  awk -v n="$listed" 'BEGIN { exit !(n > 0) }' || { echo "FAIL: no light listed"; exit 1; }
  [ "$(grep -c '^error against' "$work/ys.log")" = 2 ] || { echo "FAIL: two errors expected"; exit 1; }
done
# Another frame's image must not pass: the comparison can fail.
if "$ys" "$work/a" --runs 1 --compare "$work/b/image.exr" --max-error 2e-6 > "$work/bad.log" 2>&1; then
  cat "$work/bad.log"
  echo "FAIL: frame 0's image passed as frame 30's"
  exit 1
fi
grep -q "above --max-error" "$work/bad.log"
echo "yardstick_test: ok"
