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
# shell); --halt: the first shard that fails stops the others; --tag: each line says its shard.
parallel -q --will-cite --halt now,fail=1 --tag -j "${JOBS:-$n}" \
  "$bin" bench "$@" --quiet --resume --shard "{}/$n" --out "$out/shard-{}" ::: $(seq 0 $((n - 1)))
shards=()
for ((k = 0; k < n; k++)); do shards+=("$out/shard-$k"); done
# The merged files are made from the shards: a rerun replaces them.
exec "$bin" bench merge --overwrite "$out" "${shards[@]}"
