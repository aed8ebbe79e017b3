#!/usr/bin/env bash
# Builds the measurement-only tileshade (no OpenImageIO) from the packages in .deps/ (see
# scripts/gpu-bench-fetch.sh) and runs the committed benchmark configurations on an OpenCL device.
#   scripts/gpu-bench.sh OUT_DIR [DEVICE] [CONFIG ...]
# DEVICE defaults to "gpu"; CONFIG names files in bench/configs/ (default: pocl-targets,
# paper-tables and paper-tables-forward). NVIDIA's OpenCL driver is registered with the ICD loader
# first when present, and its EGL driver with GLVND. Configurations with "raster": "gl" run only
# where a headless OpenGL context can be made (a one-frame probe); otherwise the run says why and
# skips them.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:?usage: scripts/gpu-bench.sh OUT_DIR [DEVICE] [CONFIG ...]}
device=${2:-gpu}
shift $(( $# >= 2 ? 2 : 1 ))
configs=("$@")
[ ${#configs[@]} -eq 0 ] && configs=(pocl-targets paper-tables paper-tables-forward)

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

# GLVND finds a vendor's EGL library through a JSON file; a container that mounts NVIDIA's driver
# libraries may not ship one.
egl_nvidia=/usr/local/nvidia/lib64/libEGL_nvidia.so.0
if [ -e "$egl_nvidia" ] && ! grep -qs nvidia /usr/share/glvnd/egl_vendor.d/*.json \
  /etc/glvnd/egl_vendor.d/*.json; then
  mkdir -p .deps/egl_vendor.d
  printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s"}}\n' "$egl_nvidia" \
    > .deps/egl_vendor.d/10_nvidia.json
  export __EGL_VENDOR_LIBRARY_DIRS="$PWD/.deps/egl_vendor.d:/etc/glvnd/egl_vendor.d:/usr/share/glvnd/egl_vendor.d"
fi

with_gl=OFF
if [ -e "$prefix/usr/include/epoxy/egl.h" ] || [ -e /usr/include/epoxy/egl.h ]; then with_gl=ON; fi
cmake -S . -B build-gpu -DCMAKE_BUILD_TYPE=Release -DTILESHADE_WITH_OIIO=OFF -DTILESHADE_BUILD_TESTS=OFF -DTILESHADE_WITH_GL=$with_gl \
  -DTILESHADE_WITH_EMBREE=OFF \
  -DCMAKE_PREFIX_PATH="$prefix/usr;$prefix/usr/lib/x86_64-linux-gnu/cmake;$prefix/usr/share/cmake" \
  -DCMAKE_CXX_FLAGS="-I$prefix/usr/include" >/dev/null
cmake --build build-gpu -j "$(nproc)" --target tileshade
./build-gpu/tileshade devices
mkdir -p "$out"

# One small frame through OpenGL and a forward technique: can this machine run the "raster": "gl"
# configurations at all?
gl_ok=0
gl_why="built without libepoxy (TILESHADE_WITH_GL=OFF)"
if [ "$with_gl" = ON ]; then
  if ./build-gpu/tileshade render --raster gl --technique tiled-forward --width 64 --height 36 \
    --device "$device" --out "$out/gl-probe" >"$out/gl-probe.log" 2>&1; then
    gl_ok=1
  else
    gl_why=$(grep -m1 -i "error\|fail\|cannot\|no " "$out/gl-probe.log" || tail -n1 "$out/gl-probe.log")
  fi
fi
for c in "${configs[@]}"; do
  if [ $gl_ok = 0 ] && grep -q '"raster": *"gl"' "bench/configs/$c.json"; then
    echo "gpu-bench: skipping $c: it needs --raster gl, and no OpenGL context here: $gl_why" >&2
    continue
  fi
  ./build-gpu/tileshade bench --config "bench/configs/$c.json" --device "$device" \
    --out "$out/$c" --quiet
done
