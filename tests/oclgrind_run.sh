#!/usr/bin/env bash
# Runs a command under Oclgrind (an OpenCL device simulator that checks every kernel for
# out-of-bounds and uninitialised accesses, data races and barrier divergence) and fails on any
# report it logs, or on the command's own failure. CTest's `oclgrind` label (tests/extra_tests.cmake).
# Usage: oclgrind_run.sh "OCLGRIND OPTIONS" COMMAND ARGS...   (an argument @OUT@ becomes a
# temporary folder)
# Exit status 77 (CTest: skipped) when oclgrind is not installed (scripts/setup.sh installs it).
set -uo pipefail
options=$1
shift
command -v oclgrind >/dev/null || { echo "oclgrind is not installed: skipped"; exit 77; }
log=$(mktemp)
out=$(mktemp -d)
trap 'rm -rf "$log" "$out"' EXIT
args=()
for a in "$@"; do [ "$a" = "@OUT@" ] && args+=("$out") || args+=("$a"); done
# shellcheck disable=SC2086  # the options are meant to split into words
TILESHADE_DEVICE=oclgrind oclgrind --log "$log" $options "${args[@]}" 2>&1 | tail -n 20
status=${PIPESTATUS[0]}
if [ -s "$log" ]; then
  echo "Oclgrind reported (first 60 lines of $(grep -c . "$log") in the log):"
  head -n 60 "$log"
  exit 1
fi
[ "$status" -eq 0 ] || { echo "exit status $status"; exit 1; }
echo "no Oclgrind report"
