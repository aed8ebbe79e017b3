#!/usr/bin/env bash
# tileshade against the CPU-native yardstick on one frame, in one run (issue #19):
#   bench/yardstick/run.sh [BUILD_DIR] [OUT]      (defaults: build, /tmp/yardstick)
# Dumps street/many frame 30 at 1280x720 (render --dump, with tiled's image), then ROUNDS times
# (default 3), interleaved so each sees the same machine: the yardstick's serial form on one thread
# and on every core, its SIMD form (--simd, SIMD lanes) the same two ways, and tileshade bench on
# the dump: tiled and tiled-single at 16x16, 32x32 and 64x64 tiles (the best of which is the "best
# tile"). Prints per entry the best of the rounds' medians and its ratio to the serial yardstick
# and to the SIMD yardstick on one thread and on every core, the yardstick's phases (depth bounds +
# culling against shading, last round) and both forms' error against tiled's image.
# Environment: ROUNDS, FRAMES (bench's timed frames per round, default 3), RUNS (yardstick runs per
# round, default 3), RESOLUTION (default 1280x720), DEVICE (default cpu), SIMD (lanes, 16 or 8;
# default 16).
set -euo pipefail
build="${1:-build}"
out="${2:-/tmp/yardstick}"
rounds="${ROUNDS:-3}" frames="${FRAMES:-3}" runs="${RUNS:-3}" simd="${SIMD:-16}"
resolution="${RESOLUTION:-1280x720}" device="${DEVICE:-cpu}"
ts="$build/tileshade" ys="$build/tileshade-yardstick"
for b in "$ts" "$ys"; do
  [ -x "$b" ] || { echo "run.sh: $b not built (cmake --build $build)" >&2; exit 1; }
done
mkdir -p "$out"
dump="$out/dump"
"$ts" render --scene builtin:street --lights many --width "${resolution%x*}" \
  --height "${resolution#*x}" --frame 30 --technique tiled --device "$device" --dump \
  --out "$dump" > "$out/render.log"

results="$out/results.txt"
: > "$results"
for r in $(seq 1 "$rounds"); do
  : > "$out/phases.log"
  for form in "serial 1 0" "threaded 0 0" "simd 1 $simd" "simd-threaded 0 $simd"; do
    # shellcheck disable=SC2086  # "NAME THREADS SIMD", meant to split
    set -- $form
    "$ys" "$dump" --runs "$runs" --threads "$2" --simd "$3" > "$out/yardstick.log"
    ms=$(sed -n 's/.*median \([0-9.]*\) ms.*/\1/p' "$out/yardstick.log")
    echo "yardstick $1 $ms" >> "$results"
    echo "yardstick $1: $(sed -n 's/^phases (\(.*\)): /\1: /p' "$out/yardstick.log")" >> "$out/phases.log"
  done
  "$ts" bench --scene "gbuffer:$dump" --resolution "$resolution" --device "$device" \
    --technique tiled,tiled-single --tile 16,32,64 --frames "$frames" --warmup 1 \
    --no-calibrate --quiet --out "$out/bench-$r" > "$out/bench.log"
  python3 - "$out/bench-$r/summary.csv" >> "$results" <<'EOF'
import csv, sys
for row in csv.DictReader(open(sys.argv[1])):
    print(f"{row['technique']} {row['tile']} {row['total_ms_median']}")
EOF
done
"$ys" "$dump" --runs 1 --compare "$dump/image.exr" > "$out/error.log"
"$ys" "$dump" --runs 1 --simd "$simd" --compare "$dump/image.exr" > "$out/error-simd.log"

python3 - "$results" "$rounds" <<'EOF'
import sys
best = {}
for line in open(sys.argv[1]):
    *name, ms = line.split()
    key = " ".join(name)
    best[key] = min(best.get(key, float("inf")), float(ms))
serial, simd, simd_t = (best[f"yardstick {k}"] for k in ("serial", "simd", "simd-threaded"))
def tile_of(k): return int(k.split()[1].split("x")[0])
rows = [(f"yardstick {k}", best[f"yardstick {k}"])
        for k in ("serial", "threaded", "simd", "simd-threaded")]
for tech in ("tiled", "tiled-single"):
    mine = {k: v for k, v in best.items() if k.split()[0] == tech}
    for k in sorted(mine, key=tile_of):
        rows.append((k, mine[k]))
    b = min(mine, key=mine.get)
    rows.append((f"{tech} best tile ({b.split()[1]})", mine[b]))
print(f"best of {sys.argv[2]} interleaved rounds (median ms per round)")
print(f"{'':34} {'ms':>9} {'/ serial':>9} {'/ simd':>9} {'/ simd-threaded':>15}")
for name, ms in rows:
    print(f"{name:34} {ms:9.2f} {ms / serial:9.2f} {ms / simd:9.2f} {ms / simd_t:15.2f}")
EOF
cat "$out/phases.log"
sed -n 's/^error against/yardstick serial error against/p' "$out/error.log"
sed -n 's/^error against/yardstick simd error against/p' "$out/error-simd.log"
