#!/usr/bin/env bash
# Quick start 1: build, then render the default built-in scene with every technique on the
# default OpenCL device, check against the double reference, print the table, write out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/tileshade render --technique all --check --out out "$@"
