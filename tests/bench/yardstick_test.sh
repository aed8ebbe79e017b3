#!/usr/bin/env bash
# The CPU-native yardstick (bench/yardstick/yardstick.cpp) shades what tileshade shades: on a tiny
# street/many dump (96x54, seconds), serial and threaded, in its serial form and its SIMD form (8
# and 16 lanes), and on its metallic-roughness + spot + sun variant, its image agrees with the `tiled` image of the same dump and with the double
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
for run in "a 1 0" "a 2 0" "c 2 0" "a 1 16" "a 2 16" "c 1 16" "c 2 16" "a 1 8" "c 2 8"; do
  # shellcheck disable=SC2086  # "DUMP THREADS SIMD", meant to split
  set -- $run
  "$ys" "$work/$1" --runs 1 --threads "$2" --simd "$3" --reference \
    --compare "$work/$1/image.exr" --max-error 2e-6 > "$work/ys.log" ||
    { cat "$work/ys.log"; echo "FAIL: $run"; exit 1; }
  cat "$work/ys.log"
  # The form asked for is the form that ran.
  if [ "$3" = 0 ]; then form="serial"; else form="simd $3 lanes"; fi
  grep -q "threads $2, $form:" "$work/ys.log" || { echo "FAIL: $run did not run $form"; exit 1; }
  # Culling ran and listed lights; both comparisons were made.
  grep -q "lights listed per tile" "$work/ys.log"
  listed=$(sed -n 's/.*; \([0-9.]*\) lights listed per tile/\1/p' "$work/ys.log")
  awk -v n="$listed" 'BEGIN { exit !(n > 0) }' || { echo "FAIL: no light listed"; exit 1; }
  [ "$(grep -c '^error against' "$work/ys.log")" = 2 ] || { echo "FAIL: two errors expected"; exit 1; }
done
# Another frame's image must not pass, in either form: the comparison can fail.
for simd in 0 16; do
  if "$ys" "$work/a" --runs 1 --simd "$simd" --compare "$work/b/image.exr" --max-error 2e-6 \
    > "$work/bad.log" 2>&1; then
    cat "$work/bad.log"
    echo "FAIL: frame 0's image passed as frame 30's (--simd $simd)"
    exit 1
  fi
  grep -q "above --max-error" "$work/bad.log"
done
# A width the SIMD form does not have is refused.
if "$ys" "$work/a" --runs 1 --simd 4 > "$work/bad.log" 2>&1; then
  echo "FAIL: --simd 4 accepted"
  exit 1
fi
echo "yardstick_test: ok"
