#!/usr/bin/env bash
# Quick start 2: build, then run every test (kernels on the CPU through PoCL unless
# TILESHADE_DEVICE says otherwise).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build && ctest --output-on-failure -j "$(nproc)" "$@"
