#!/usr/bin/env bash
# Prints one line per output file of a fixed set of `render` and `bench` runs on the built-in
# scenes: its name and a hash of what does not depend on timing (images, G-buffer dumps, and
# stats.json / bench.csv with every time column removed). A refactor that changes no behaviour
# prints the same lines (issue #15: output unchanged bit for bit).
#   scripts/output_fingerprint.sh BUILD_DIR > fingerprint.txt
set -euo pipefail
bin="$(cd "${1:?usage: output_fingerprint.sh BUILD_DIR}" && pwd)/tileshade"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export TILESHADE_DEVICE="${TILESHADE_DEVICE:-cpu}"

run() {  # name, render options...
  local name="$1"; shift
  "$bin" render --width 96 --height 54 --out "$work/$name" "$@" > /dev/null 2>&1 ||
    { echo "$name: render failed" >&2; exit 1; }
}
run street-all --technique all --check --dump
run street-packed --technique all --gbuffer packed --check
run street-fp16-32 --technique tiled clustered tiled-single --gbuffer fp16 --tile 32 --culling aabb
run street-split --technique tiled --depth-split --culling frustum --math fast
run street-native --technique tiled brute --math native --lanes 4
run atrium-big --scene builtin:atrium --lights big --technique all --check --slices 8
run atrium-mr --scene builtin:atrium --variant metallic-roughness,spot,sun --technique all --check --spot-culling bound-sphere
run street-range --technique all --light-threshold 0.02 --light-count 300 --seed 7 --check
run street-gl --raster gl --technique tiled --check --dump
"$bin" render --gbuffer-in "$work/street-all" --technique all --check --out "$work/reimport" \
  > /dev/null 2>&1 || { echo "reimport: render failed" >&2; exit 1; }
"$bin" bench --quiet --no-calibrate --technique all --resolution 96x54 --frames 2 --error \
  --gbuffer fp32,packed --scene builtin:street,builtin:atrium --out "$work/bench" > /dev/null 2>&1 ||
  { echo "bench failed" >&2; exit 1; }

# stats.json and bench.csv/json without times, devices and dates.
strip_py='
import csv, json, re, sys
timey = re.compile(r"(^|_)(ms|time|times|date|utc|command|compile|seconds|gflops|gbps|limit|pct|calib|device|host|kernels|fraction|started|finished)($|_)")
def clean(v):
    if isinstance(v, dict):
        return {k: clean(x) for k, x in v.items() if not timey.search(k)}
    if isinstance(v, list):
        return [clean(x) for x in v]
    return v
p = sys.argv[1]
text = open(p).read().replace(sys.argv[2], "WORK")  # the scratch folder differs per run
if p.endswith(".json"):
    print(json.dumps(clean(json.loads(text)), sort_keys=True))
else:
    for row in csv.DictReader(text.splitlines()):
        print(json.dumps({k: x for k, x in row.items() if not timey.search(k)}, sort_keys=True))
'
# EXR files without the capDate attribute OpenImageIO writes (the time of writing).
exr_py='
import re, sys
data = open(sys.argv[1], "rb").read()
sys.stdout.buffer.write(re.sub(rb"capDate\x00string\x00.{4}\d{4}:\d\d:\d\d \d\d:\d\d:\d\d", b"", data, flags=re.S))
'
cd "$work"
find . -type f | LC_ALL=C sort | while read -r f; do
  case "$f" in
    *.json|*.csv) h=$(python3 -c "$strip_py" "$f" "$work" | sha256sum | cut -c1-16) ;;
    *.exr) h=$(python3 -c "$exr_py" "$f" | sha256sum | cut -c1-16) ;;
    *) h=$(sha256sum < "$f" | cut -c1-16) ;;
  esac
  echo "$f $h"
done
