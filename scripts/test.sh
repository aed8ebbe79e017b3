#!/usr/bin/env bash
# Quick start 2 (and CI): build, then run every test, in stages, each timed:
#   1. release    the Release build (./build) and its CTest suite (kernels on the CPU through PoCL
#                 unless TILESHADE_DEVICE says otherwise); extra arguments go to this ctest
#   2. sanitize   an AddressSanitizer + UndefinedBehaviorSanitizer build with clang (./build-asan,
#                 also holding the fuzz targets) and the whole CTest suite in it, PoCL kernels
#                 included (TILESHADE_SANITIZE_CTEST_ARGS, default "-LE oclgrind -E /lights_1e5[^_]":
#                 not the slow Oclgrind-simulated kernel tests, nor the hard case of 1e5 lights,
#                 whose double reference takes 39 s in Release and over 10 min instrumented; the
#                 release stage runs both)
#   3. fuzz       each libFuzzer target for TILESHADE_FUZZ_SECONDS (default 60) over its seeds
# ./scripts/test.sh --quick (or TILESHADE_QUICK=1) runs stage 1 only.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=${TILESHADE_QUICK:-0}
ctest_args=()
for a in "$@"; do
  if [ "$a" = "--quick" ]; then quick=1; else ctest_args+=("$a"); fi
done
fuzz_seconds=${TILESHADE_FUZZ_SECONDS:-60}
jobs=$(nproc)

stage_start=$SECONDS
stage() {  # stage NAME: prints the previous stage's time, then NAME
  local now=$SECONDS
  [ -n "${current:-}" ] && echo "test.sh: stage '$current' took $((now - stage_start)) s"
  current=$1
  stage_start=$now
  [ -n "$current" ] && echo "test.sh: stage '$current'"
  return 0
}

stage release
bash scripts/build.sh
(cd build && ctest --output-on-failure -j "$jobs" "${ctest_args[@]}")

if [ "$quick" = 1 ]; then
  stage ""
  echo "test.sh: --quick: sanitizer and fuzzing stages skipped"
  exit 0
fi

stage sanitize
# Release flags, then -O1 with the sanitizers (cmake/sanitizers.cmake). Leaks are checked in the
# fuzz stage, not here: these tests run PoCL in the process, whose own allocations LeakSanitizer
# reports at exit, and whose worker threads now and then crash LeakSanitizer's exit-time tracer
# ("Tracer caught signal 11"), so a leak report here says nothing about our code.
CC=clang CXX=clang++ cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Release -DTILESHADE_FUZZ=ON >/dev/null
cmake --build build-asan -j "$jobs"
asan_options=${ASAN_OPTIONS:-}
export ASAN_OPTIONS=${asan_options:-detect_leaks=0:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
read -r -a sanitize_args <<< "${TILESHADE_SANITIZE_CTEST_ARGS:--LE oclgrind -E /lights_1e5[^_]}"
(cd build-asan && ctest --output-on-failure -j "$jobs" "${sanitize_args[@]}")

stage fuzz
# No OpenCL runs here: the loaders and the config parser, with LeakSanitizer.
export ASAN_OPTIONS=${asan_options:-detect_leaks=1:abort_on_error=1}
work=$PWD/build-asan/fuzz
fuzzers=$PWD/build-asan/tests/fuzz
mkdir -p "$work/builtins" "$work/assimp"
# The exporter's own files: run once each (at ~1 MB they are too large to fuzz efficiently).
./build/tileshade scene export builtin:street "$work/builtins/street.glb" --lights few >/dev/null
./build/tileshade scene export builtin:atrium "$work/builtins/atrium.gltf" --lights small >/dev/null
"$fuzzers/gltf_fuzzer" "$work/builtins/street.glb" "$work/builtins/atrium.gltf" >/dev/null 2>&1
echo "test.sh: the exported built-in scenes load under the sanitizers"
# Debian's assimp-testmodels: small valid and deliberately broken glTF files, as more seeds.
find /usr/share/assimp/models/glTF2 \( -name '*.gltf' -o -name '*.glb' \) -size -64k \
  -exec cp {} "$work/assimp/" \; 2>/dev/null || true

run_fuzzer() {  # run_fuzzer NAME DICT SEED_DIR...
  local name=$1 dict=$2
  shift 2
  mkdir -p "$work/$name/corpus"
  echo "test.sh: $name for ${fuzz_seconds} s"
  (cd "$work/$name" && "$fuzzers/$name" -max_total_time="$fuzz_seconds" -timeout=25 \
     -rss_limit_mb=4096 -malloc_limit_mb=3072 -max_len=65536 -dict="$dict" -print_final_stats=1 \
     corpus "$@" 2>&1 | grep -v -E '^(#[0-9]+[[:space:]]+(NEW|REDUCE|pulse|INITED)|"|###### |[[:space:]]+NEW_FUNC)' | tail -n 40)
}
run_fuzzer gltf_fuzzer "$PWD/tests/fuzz/gltf.dict" "$PWD/tests/fuzz/seeds/gltf" "$PWD/tests/data/fuzz" \
  "$work/assimp"
run_fuzzer bench_config_fuzzer "$PWD/tests/fuzz/bench_config.dict" "$PWD/tests/fuzz/seeds/bench_config" \
  "$PWD/bench/configs" "$PWD/tests/data/fuzz"
run_fuzzer gbuffer_descriptor_fuzzer "$PWD/tests/fuzz/gbuffer_descriptor.dict" \
  "$PWD/tests/fuzz/seeds/gbuffer_descriptor"
run_fuzzer lights_fuzzer "$PWD/tests/fuzz/lights.dict" "$PWD/tests/fuzz/seeds/lights"
stage ""
