#!/usr/bin/env bash
# Measures what each kernel change bought, in one run: the kernels of each git revision given
# (their kernels/ folder, checked out into OUT_DIR), or of a folder of kernels given by its path,
# run by the same tileshade binary
# (kernels are compiled at run time from $TILESHADE_KERNEL_DIR), interleaved so that every
# revision sees the same machine state. Prints, per revision, the median per-kernel times.
#   bench/kernel-steps.sh OUT_DIR ROUNDS REV... [-- BENCH_OPTIONS...]
# The revisions' kernels must take the arguments this binary passes (true from the
# feature-specialised kernels on). Default bench options: tiled, street/many, 1280x720, 4 frames.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: bench/kernel-steps.sh OUT_DIR ROUNDS REV... [-- BENCH_OPTIONS...]}
rounds=${2:?rounds}
shift 2
revs=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do revs+=("$1"); shift; done
[ $# -gt 0 ] && shift
opts=("$@")
[ ${#opts[@]} -eq 0 ] && opts=(--scene builtin:street --lights many --resolution 1280x720
                               --technique tiled --frames 4 --error)
mkdir -p "$out"
declare -A dirs
for rev in "${revs[@]}"; do
  if [ -d "$rev" ]; then dirs[$rev]=$(cd "$rev" && pwd); continue; fi
  dir="$out/kernels-$rev"
  rm -rf "$dir" && mkdir -p "$dir"
  git archive "$rev" kernels | tar -x -C "$dir" --strip-components=1
  dirs[$rev]=$(cd "$dir" && pwd)
done
label() { basename "$1"; }
for ((r = 0; r < rounds; ++r)); do
  for rev in "${revs[@]}"; do
    name=$(label "$rev")
    TILESHADE_KERNEL_DIR="${dirs[$rev]}" ./build/tileshade bench "${opts[@]}" --quiet \
      --overwrite --no-calibrate --out "$out/$name-round$r" > "$out/$name-round$r.txt"
  done
done
names=()
for rev in "${revs[@]}"; do names+=("$(label "$rev")"); done
/usr/bin/python3 - "$out" "$rounds" "${names[@]}" <<'PY'
import csv, statistics, sys
out, rounds, revs = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
for rev in revs:
    per = {}
    for r in range(rounds):
        for row in csv.DictReader(open(f"{out}/{rev}-round{r}/bench.csv")):
            key = (row["technique"], row["lanes_used"])
            per.setdefault(key, {}).setdefault("total", []).append(float(row["total_ms"]))
            for item in row["kernels"].split(";"):
                name, ms = item.split("=")
                per[key].setdefault(name, []).append(float(ms))
    for key, d in per.items():
        parts = " ".join(f"{k}={statistics.median(v):.2f}" for k, v in d.items() if k != "total")
        print(f"{rev} {key[0]} lanes {key[1]}: total median {statistics.median(d['total']):.2f} ms "
              f"(n={len(d['total'])}) | {parts}")
PY
