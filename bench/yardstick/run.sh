#!/usr/bin/env bash
# tileshade against the CPU-native yardstick on one frame, in one run (issue #19):
#   bench/yardstick/run.sh [BUILD_DIR] [OUT]      (defaults: build, /tmp/yardstick)
# Dumps street/many frame 30 at 1280x720 (render --dump, with tiled's image), then ROUNDS times
# (default 3), interleaved so each sees the same machine: the yardstick serial and threaded, and
# tileshade bench on the dump: tiled and tiled-single at 16x16, 32x32 and 64x64 tiles (the best of
# which is the "best tile"). Prints per entry the best of the rounds' medians and its ratio to
# the serial and the threaded yardstick, and the yardstick's error against tiled's image.
# Environment: ROUNDS, FRAMES (bench's timed frames per round, default 3), RUNS (yardstick runs per
# round, default 3), RESOLUTION (default 1280x720), DEVICE (default cpu).
set -euo pipefail
build="${1:-build}"
out="${2:-/tmp/yardstick}"
rounds="${ROUNDS:-3}" frames="${FRAMES:-3}" runs="${RUNS:-3}"
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
  for t in 1 0; do
    "$ys" "$dump" --runs "$runs" --threads "$t" > "$out/yardstick.log"
    ms=$(sed -n 's/.*median \([0-9.]*\) ms.*/\1/p' "$out/yardstick.log")
    echo "yardstick $([ "$t" = 1 ] && echo serial || echo threaded) $ms" >> "$results"
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

python3 - "$results" "$rounds" <<'EOF'
import sys
best = {}
for line in open(sys.argv[1]):
    *name, ms = line.split()
    key = " ".join(name)
    best[key] = min(best.get(key, float("inf")), float(ms))
serial, threaded = best["yardstick serial"], best["yardstick threaded"]
def tile_of(k): return int(k.split()[1].split("x")[0])
rows = [("yardstick serial", serial), ("yardstick threaded", threaded)]
for tech in ("tiled", "tiled-single"):
    mine = {k: v for k, v in best.items() if k.split()[0] == tech}
    for k in sorted(mine, key=tile_of):
        rows.append((k, mine[k]))
    b = min(mine, key=mine.get)
    rows.append((f"{tech} best tile ({b.split()[1]})", mine[b]))
print(f"best of {sys.argv[2]} interleaved rounds (median ms per round)")
print(f"{'':34} {'ms':>9} {'/ serial':>9} {'/ threaded':>10}")
for name, ms in rows:
    print(f"{name:34} {ms:9.2f} {ms / serial:9.2f} {ms / threaded:10.2f}")
EOF
sed -n 's/^error against/yardstick error against/p' "$out/error.log"
