#!/usr/bin/env bash
# The shard recipes of bench/README.md end to end on a small sweep: the shards run as separate
# processes and merged by `tileshade bench merge` equal one unsharded run's bench.csv and
# summary.csv apart from the time columns, row order included.
#   tests/bench/bench_shards_test.sh parallel|slurm TILESHADE_BINARY SOURCE_DIR
# parallel: bench/parallel/run_shards.sh with GNU parallel (exit 77, skipped, where it is absent).
# slurm: bench/slurm/bench_array.sbatch run by bash as the tasks of an array of 3 would run it
# (SLURM_ARRAY_* set by hand), then as the dependent merge job.
set -euo pipefail
mode="${1:?usage: bench_shards_test.sh parallel|slurm BINARY SOURCE_DIR}"
bin="${2:?binary}"
src="${3:?source dir}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export TILESHADE="$bin" TILESHADE_DEVICE="${TILESHADE_DEVICE:-cpu}"
sweep=(--device cpu --resolution 64x36,48x32 --gbuffer fp32,fp16 --technique tiled
       --tile 16,32x16 --frames '0;20' --warmup 0 --no-calibrate)

case "$mode" in
  parallel)
    command -v parallel >/dev/null || { echo "SKIP: GNU parallel is not installed (Debian package parallel)"; exit 77; }
    JOBS=2 bash "$src/bench/parallel/run_shards.sh" "$work/sharded" 3 "${sweep[@]}" > "$work/log" ||
      { cat "$work/log"; exit 1; }
    ;;
  slurm)
    bash -n "$src/bench/slurm/bench_array.sbatch"
    for k in 0 1 2; do
      SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_COUNT=3 SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_MAX=2 \
        bash "$src/bench/slurm/bench_array.sbatch" "$work/sharded" "${sweep[@]}" > "$work/log"
    done
    bash "$src/bench/slurm/bench_array.sbatch" --merge "$work/sharded" > "$work/log"
    # An array that is not 0..n-1 would leave shards out: refused.
    if SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=2 \
        bash "$src/bench/slurm/bench_array.sbatch" "$work/bad" "${sweep[@]}" 2> "$work/err"; then
      echo "an array 1-2 was not refused"; exit 1
    fi
    grep -q "the array must be 0-1" "$work/err" || { cat "$work/err"; exit 1; }
    ;;
  *) echo "unknown mode $mode"; exit 2 ;;
esac
grep -q "3 shard(s) of a sweep of 8 configuration(s); 16 row(s)" "$work/log" || { cat "$work/log"; exit 1; }

"$bin" bench "${sweep[@]}" --quiet --out "$work/whole" > /dev/null
# Each file without its time columns (bench_merge_test.cpp checks the rest of bench.json).
untimed() {
  python3 - "$1" <<'PY'
import csv, re, sys
timey = re.compile(r"(_ms|kernels|limit|gbs|gflops)")
for row in csv.DictReader(open(sys.argv[1])):
    print({k: v for k, v in row.items() if not timey.search(k)})
PY
}
for f in bench.csv summary.csv; do
  diff <(untimed "$work/whole/$f") <(untimed "$work/sharded/$f") > "$work/diff" ||
    { echo "merged $f differs from the unsharded run's:"; head -20 "$work/diff"; exit 1; }
done
[ "$(wc -l < "$work/sharded/bench.csv")" = 17 ] || { echo "expected 16 rows"; exit 1; }
echo "ok: $mode shards merged equal the unsharded run"
