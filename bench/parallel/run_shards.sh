#!/usr/bin/env bash
# Runs one bench sweep as N shards in parallel local processes with GNU parallel (Debian package
# `parallel`), then joins them with `tileshade bench merge` (bench/README.md, "Sweeps beyond one
# process"):
#   bench/parallel/run_shards.sh OUT N [BENCH_OPTIONS...]
# Shard k writes OUT/shard-k (resumed when run again: an interrupted sweep goes on); OUT gets the
# merged bench.csv, bench.json and summary.csv, as one unsharded run writes them. At most JOBS
# shards run at once (default: N); TILESHADE names the binary (default: build/tileshade of this
# checkout). Do not pass --out, --shard or --resume yourself.
set -euo pipefail
usage="usage: run_shards.sh OUT N [BENCH_OPTIONS...]"
out="${1:?$usage}"
n="${2:?$usage}"
shift 2
[[ "$n" =~ ^[1-9][0-9]{0,5}$ ]] || { echo "run_shards.sh: error: N must be 1..999999, got '$n'" >&2; exit 1; }
command -v parallel >/dev/null || { echo "run_shards.sh: error: GNU parallel is not installed (Debian: apt-get install parallel)" >&2; exit 1; }
bin="${TILESHADE:-$(cd "$(dirname "$0")/../.." && pwd)/build/tileshade}"
[ -x "$bin" ] || { echo "run_shards.sh: error: no tileshade binary at $bin (set TILESHADE)" >&2; exit 1; }
mkdir -p "$out"
# -q: the options reach tileshade as they are (a frame list such as '0;4;8' is not split by a
# shell); --tag: each line says its shard. A shard with a failed configuration still writes its
# other rows and exits 1, as one run does: every shard runs to its end, the merge follows, and
# the script's status is then parallel's (the number of shards that failed).
status=0
parallel -q --will-cite --tag -j "${JOBS:-$n}" \
  "$bin" bench "$@" --quiet --resume --shard "{}/$n" --out "$out/shard-{}" ::: $(seq 0 $((n - 1))) ||
  status=$?
shards=()
for ((k = 0; k < n; k++)); do shards+=("$out/shard-$k"); done
# The merged files are made from the shards: a rerun replaces them.
"$bin" bench merge --overwrite "$out" "${shards[@]}"
[ "$status" -eq 0 ] || echo "run_shards.sh: error: $status shard(s) failed (reasons above); the merge holds the rows they wrote" >&2
exit "$status"
