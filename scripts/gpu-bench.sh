#!/usr/bin/env bash
# Builds the measurement-only tileshade (no OpenImageIO) from the packages in .deps/ (see
# scripts/gpu-bench-fetch.sh) and runs the committed benchmark configurations on an OpenCL device.
#   scripts/gpu-bench.sh OUT_DIR [DEVICE] [CONFIG ...]
# DEVICE defaults to "gpu"; CONFIG names files in bench/configs/ (default: pocl-targets and
# paper-tables). NVIDIA's OpenCL driver is registered with the ICD loader first when present.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/gpu-bench.sh OUT_DIR [DEVICE] [CONFIG ...]}
device=${2:-gpu}
shift $(( $# >= 2 ? 2 : 1 ))
configs=("$@")
[ ${#configs[@]} -eq 0 ] && configs=(pocl-targets paper-tables)

nvidia=/usr/local/nvidia/lib64/libnvidia-opencl.so.1
if [ -e "$nvidia" ] && [ ! -e /etc/OpenCL/vendors/nvidia.icd ]; then
  mkdir -p /etc/OpenCL/vendors
  echo "$nvidia" > /etc/OpenCL/vendors/nvidia.icd
fi

prefix=$PWD/.deps/root
if [ -d .deps ] && ls .deps/*.deb >/dev/null 2>&1; then
  mkdir -p "$prefix"
  for f in .deps/*.deb; do dpkg -x "$f" "$prefix"; done
fi
export LD_LIBRARY_PATH="$prefix/usr/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
cmake -S . -B build-gpu -DCMAKE_BUILD_TYPE=Release -DTILESHADE_WITH_OIIO=OFF -DTILESHADE_BUILD_TESTS=OFF -DTILESHADE_WITH_GL=OFF \
  -DTILESHADE_WITH_EMBREE=OFF \
  -DCMAKE_PREFIX_PATH="$prefix/usr;$prefix/usr/lib/x86_64-linux-gnu/cmake;$prefix/usr/share/cmake" \
  -DCMAKE_CXX_FLAGS="-I$prefix/usr/include" >/dev/null
cmake --build build-gpu -j "$(nproc)" --target tileshade
./build-gpu/tileshade devices
mkdir -p "$out"
for c in "${configs[@]}"; do
  ./build-gpu/tileshade bench --config "bench/configs/$c.json" --device "$device" \
    --out "$out/$c" --quiet
done
