#!/usr/bin/env bash
# Installs the Debian 12 packages tileshade needs, only those that are missing.
# Idempotent: a machine that already has everything runs no apt-get at all.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  opencl-headers ocl-icd-opencl-dev opencl-clhpp-headers pocl-opencl-icd clinfo
  libglm-dev libopenimageio-dev libtinygltf-dev libcli11-dev nlohmann-json3-dev
  libembree-dev  # exact visibility, the shadows' second reference (src/visibility/)
  libgtest-dev python3-matplotlib assimp-testmodels
  # --raster gl: EGL + Mesa's llvmpipe (headless OpenGL without a GPU), GL loaded by libepoxy
  libegl-dev libegl1 libegl-mesa0 libgl1-mesa-dri libepoxy-dev
  oclgrind  # the kernels under an OpenCL checker (CTest label oclgrind, tests/extra_tests.cmake)
  parallel  # bench/parallel/run_shards.sh: a sweep's shards as local processes (CTest BenchShards.parallel)
  # the sanitizer build and the fuzzers of scripts/test.sh (clang's ASan/UBSan/libFuzzer runtimes,
  # llvm-symbolizer for readable reports)
  clang libclang-rt-14-dev llvm
  # the Python module (python/, CTest label python): pybind11, numpy arrays, pytest
  pybind11-dev python3-dev python3-numpy python3-pytest
  clang-format  # scripts/format_check.sh (CTest Format.ClangFormat): the layout of .clang-format
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
