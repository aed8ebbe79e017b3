#!/usr/bin/env bash
# Compiles every kernel, in the build variants the host uses, for an OpenCL 1.2 device without
# fp64 (clang's SPIR target with cl_khr_fp64 off) with warnings as errors: no double constant or
# double arithmetic may reach a device that lacks them (issue #12; constants in the shared headers
# are written TS_LIT(x), kernels/shading.h). Run by CTest (tests/extra_tests.cmake).
# Usage: kernels_without_fp64.sh CLANG KERNEL_DIR
set -euo pipefail
clang=$1
dir=$2
builds=0
failed=0

compile() {
  local file=$1
  shift
  builds=$((builds + 1))
  local out
  if ! out=$("$clang" -x cl -cl-std=CL1.2 -target spir -Xclang -finclude-default-header \
               -Xclang -cl-ext=-cl_khr_fp64 -fsyntax-only -Werror -I "$dir" "$@" "$dir/$file" 2>&1); then
    echo "FAILED: $file $*"
    echo "$out" | head -20
    failed=$((failed + 1))
  fi
}

tile="-DTILE_W=16 -DTILE_H=16"
single="$tile -DGROUP_W=16 -DGROUP_H=16 -DLIST_CAPACITY=256"
for layout in "" -DTS_GBUFFER_FP16 -DTS_GBUFFER_PACKED; do
  common="$layout -DTS_MODEL=0 -DTS_CULL=0"
  for lanes in "" -DTS_LANES=2 -DTS_LANES=16; do
    # shellcheck disable=SC2086  # the option strings are meant to split into words
    compile tiled.cl $common $lanes $tile
    compile tiled_single.cl $common $lanes $single
    compile brute.cl $common $lanes
    compile deferred.cl $common $lanes -DTS_STENCIL
  done
  compile clustered.cl $common $tile -DSLICES=16
  compile dump.cl $common
done
# The other knobs: native arithmetic, the physical model, the frustum and AABB culling tests.
compile tiled.cl -DTS_NATIVE_MATH -DTS_MODEL=1 -DTS_CULL=1 $tile
compile tiled_single.cl -DTS_NATIVE_MATH -DTS_LANES=16 -DTS_MODEL=1 -DTS_CULL=2 $single
compile clustered.cl -DTS_NATIVE_MATH -DTS_MODEL=1 -DTS_CULL=2 $tile -DSLICES=16
compile deferred.cl -DTS_NATIVE_MATH
compile calibrate.cl -DCAL_WIDTH=4 -DCAL_CHAINS=4
echo "kernels without fp64: $builds builds, $failed failed"
[ "$failed" -eq 0 ]
